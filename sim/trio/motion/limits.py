"""Software limits: where an executing move first takes an axis past FS_LIMIT / RS_LIMIT.

TRM, MC216 listing p. 8-177 (RS_LIMIT; FS_LIMIT is its forward twin): "An end of travel
software limit may be set up in software thus allowing the program control of the working
envelope of the machine. This parameter holds the absolute position of the reverse travel limit
in user units. When the limit is hit the controller will ramp down the speed to zero then cancel
the move. Bit 10 in the axis status parameter is set when the axis is in the RS_LIMIT" (bit 9
for FS_LIMIT, spec §1.6).

Modelled (:class:`motionsim.sim.trio.motion.guards.AxisGuards` acts on it):

* the limit is *hit* at the first servo period at which the axis' demand position has reached
  it while the move still drives the axis outwards: DPOS >= FS_LIMIT moving forwards, DPOS <=
  RS_LIMIT moving backwards (``[INF]``, as AXISSTATUS counts DPOS = FS_LIMIT as in the limit;
  a move that ends exactly on the limit is not cancelled);
* a move that starts with the axis already beyond a limit and heads further out is cancelled in
  its first servo period; one that heads back inside runs (``[INF]``: the way out of a limit);
* then the whole move (every axis of an interpolated group) ramps down at the base axis' DECEL
  — FASTDEC when that is set above 0 (``[BK]``: FASTDEC is the deceleration used at a limit) —
  and ends cancelled, so the axis stops beyond the limit by the ramp's distance; the move in
  NTYPE then loads as after any CANCEL (a further move outwards is cancelled at once);
* every move type that moves an axis: MOVE, MOVEABS, MOVEMODIFY, MOVESP / …SP, FORWARD /
  REVERSE (here the hit is computed from the path), MOVECIRC / MHELICAL (the arc is searched),
  and the linked moves CAM / CAMBOX / MOVELINK / CONNECT, whose position follows another axis:
  they are looked at every servo period while they run (a linked move other than CAM stops at
  once where it is, as on CANCEL);
* the position compared is the axis' own demand (what ADDAX adds is not checked, ``[INF]``);
  the DATUM(1..6) sequences are not stopped by the software limits ``[INF]``.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from .axis import Axis
    from .moves import Move

#: Samples per arc when searching a MOVECIRC / MHELICAL for its first crossing.
ARC_SAMPLES = 512
FORWARD, REVERSE = "FS_LIMIT", "RS_LIMIT"


def limits_of(ax: Axis) -> tuple[float, float]:
    """(RS_LIMIT, FS_LIMIT) of ``ax`` now."""
    st = ax.stored.values
    return st["RS_LIMIT"], st["FS_LIMIT"]


def outward(position: float, previous: float, lo: float, hi: float) -> str | None:
    """The limit an axis at ``position``, coming from ``previous``, has hit (None: none)."""
    if position >= hi and position > previous:
        return FORWARD
    if position <= lo and position < previous:
        return REVERSE
    return None


def ends_inside(m: Move, axes: list[Axis]) -> bool:
    """Whether ``m`` (with ``axes`` the controller's axes) surely passes no limit: a straight
    move of finite length is monotone on each axis, so it reaches a limit only if it ends
    beyond one (or on one it started beyond, heading out: then it ends beyond too)."""
    prof = m.profile
    if m.circ or prof is None or prof.length == math.inf:
        return False
    ms = m.axes
    if len(ms) == 1:  # (the usual move: no zip)
        st = axes[ms[0]].stored.values
        return st["RS_LIMIT"] <= m.end_pos[0] <= st["FS_LIMIT"]
    for e, a in zip(m.end_pos, ms, strict=True):
        st = axes[a].stored.values
        if not st["RS_LIMIT"] <= e <= st["FS_LIMIT"]:
            return False
    return True


def first_hit(m: Move, axes: list[Axis], s_from: float) -> tuple[float, int, str] | None:
    """The first path distance ``S >= s_from`` along the path of ``m`` (a speed-profiled move
    with a fixed path) at which one of its axes is beyond a software limit heading outwards:
    ``(S, axis, "FS_LIMIT" | "RS_LIMIT")``, or None when the move never gets there."""
    prof = m.profile
    assert prof is not None
    s_end = m.s_off + prof.length
    if s_end <= s_from:
        return None
    best: tuple[float, int, str] | None = None
    for i, ax in enumerate(axes):
        lo, hi = limits_of(ax)
        if m.circ and i < 2:
            hit = _arc_hit(m, i, lo, hi, s_from, s_end)
        elif m.circ:  # MHELICAL's third axis: straight along the path
            cx, cy, r, th0, sweep, d3, length = m.circ
            hit = _line_hit(m.p0[2], d3 / length if length > 0.0 else 0.0, lo, hi,
                            s_from, s_end)
        else:
            hit = _line_hit(m.p0[i], m.unit[i], lo, hi, s_from, s_end)
        if hit is not None and (best is None or hit[0] < best[0]):
            best = (hit[0], ax.n, hit[1])
    return best


def _line_hit(p0: float, u: float, lo: float, hi: float, s_from: float,
              s_end: float) -> tuple[float, str] | None:
    """Position ``p0 + u * S``: where it first passes ``hi`` going up or ``lo`` going down."""
    if u > 0.0:
        s, which = (hi - p0) / u, FORWARD
    elif u < 0.0:
        s, which = (lo - p0) / u, REVERSE
    else:
        return None
    s = max(s, s_from)
    return (s, which) if s < s_end else None


def _arc_hit(m: Move, i: int, lo: float, hi: float, s_from: float,
             s_end: float) -> tuple[float, str] | None:
    """Axis ``i`` of an arc: sampled, then the first crossing bisected (none when the whole
    circle lies inside the limits)."""
    centre, r = m.circ[i], m.circ[2]
    if lo < centre - r and centre + r < hi:
        return None
    def pos(s: float) -> float:
        return m.at(s)[i]

    n = max(2, int(ARC_SAMPLES * (s_end - s_from) / max(m.length, 1e-12)) + 2)
    step = (s_end - s_from) / n
    prev_s, prev = s_from, pos(s_from)
    nudge = pos(min(s_end, s_from + step * 1e-3))
    if nudge != prev and outward(prev, 2.0 * prev - nudge, lo, hi) is not None:
        return s_from, FORWARD if prev >= hi else REVERSE
    for k in range(1, n + 1):
        s = s_from + step * k if k < n else s_end
        p = pos(s)
        for bound, which, beyond in ((hi, FORWARD, p >= hi), (lo, REVERSE, p <= lo)):
            if beyond and not (prev >= hi if which == FORWARD else prev <= lo):
                a, b = prev_s, s
                for _ in range(60):
                    mid = 0.5 * (a + b)
                    if (pos(mid) >= bound) if which == FORWARD else (pos(mid) <= bound):
                        b = mid
                    else:
                        a = mid
                return (b, which) if b < s_end else None
        prev_s, prev = s, p
    return None


__all__ = ["FORWARD", "REVERSE", "ends_inside", "first_hit", "limits_of", "outward"]
