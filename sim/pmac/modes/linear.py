"""LINEAR and CIRCLE moves: timing and the blended constant-velocity profile.

Timing (TSRM p188-189, p177; spec §9.1): the move time is TM in move-by-time mode, else the
vector distance over the feedrate axes / F × Isx90 ms; CIRCLE1/2 use the arc length when
Isx13 > 0 (without segmentation they run as LINEAR, TSRM p177). With Isx13 = 0 a move that
would take any motor past its Ixx16 is made longer so all motors slow in proportion (TSRM p98,
TUM "the move time is extended so that motor will not exceed its limit"); with Isx13 > 0
Ixx16 acts only through the special lookahead (Isx20, ``DEFINE LOOKAHEAD``), which is not
modelled, so no limit applies there. With Isx13 = 0 the acceleration limit Ixx17 then
stretches the ramp into the move and the stop ramp, and can make the move longer
(:mod:`.accel_limit`). The time is at least the acceleration time ``Ta = max(TA, 2·TS)``
and is stretched by the ``%`` time base. The axes run at constant velocity between blend
ramps centred on the programmed points (:func:`motionsim.sim.pmac.buffers.motion.position_at`);
a segmented CIRCLE move (:class:`ArcMove`) adds its arc's offset from the chord, so its
positions lie on the arc. The centre vector is incremental from the start point (``INC(R)``,
the default) or absolute from the XYZ origin (``ABS(R)``; TSRM p442).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

from ..buffers import motion
from ..card.variables import ixx
from . import accel_limit
from .move import LINEAR, Move, PlanContext, Profile

if TYPE_CHECKING:
    from ..language.expressions import Expr


def plan(
    ctx: PlanContext, n: int, start: dict[str, float], end: dict[str, float],
    vectors: tuple[tuple[str, Expr], ...], w: Mapping[str, float] | None = None,
) -> Move:
    """The LINEAR / CIRCLE move of line ``n`` from ``start`` to ``end`` (``vectors``: the
    circle's I, J, K / R words; ``w``: the previous calculated LINEAR move's axis velocities
    in program time, for Ixx17 at the corner, ``None`` from rest)."""
    path: motion.Arc | None = None
    if ctx.mode != "LINEAR" and vectors and ctx.segmented:
        vars_, cs = ctx.vars, ctx.cs
        vec = dict(vectors)
        ij = (
            vec["I"](vars_, cs) if "I" in vec else 0.0,
            vec["J"](vars_, cs) if "J" in vec else 0.0,
        )
        radius = vec["R"](vars_, cs) if "R" in vec else None
        path = motion.arc(start, end, None if radius else ij, radius, ctx.mode == "CIRCLE1",
                          ctx.abs_radius)
    if ctx.time_mode:
        t = ctx.feedrate / 1000.0
    else:
        if path is not None:
            dist = path.length
        else:
            dist = motion.vector_distance({a: end[a] - start[a] for a in end}, ctx.frax)
        t = motion.feed_time_s(dist, ctx.feedrate, ctx.isx90_ms)
    lookahead = ctx.segmented and ctx.special_lookahead
    arc = ctx.segmented and ctx.mode != "LINEAR" and bool(vectors)
    if (ctx.segmented and not lookahead) or arc:
        t = motion.clamp_move_time(t, ctx.accel_prog_s) * ctx.time_scale
        if path is not None:
            return ArcMove(n, t, ctx.accel_real_s, start, end, path)
        return Move(n, LINEAR, t, ctx.accel_real_s, start, end, None)
    t = velocity_limited(ctx, start, end, t)
    t, ta, ta_stop = accel_limit.limited(ctx, start, end, t, w, lookahead=lookahead)
    scale = ctx.time_scale
    move = Move(n, LINEAR, motion.clamp_move_time(t, ta) * scale, ta * scale, start, end, None)
    move.ta_stop = ta_stop
    return move


def velocity_limited(
    ctx: PlanContext, start: dict[str, float], end: dict[str, float], t: float
) -> float:
    """The move time extended so no motor exceeds its Ixx16 (TSRM p98, Isx13 = 0: "all
    motors in the coordinate system are slowed proportionally", same path). Velocities are
    compared at 100 % (program time); an axis with no motor assigned has no limit ``[INF]``."""
    if t <= 0:
        return t
    worst = 1.0
    for axis, p1 in end.items():
        d = abs(p1 - start.get(axis, 0.0))
        if d == 0:
            continue
        for motor, scale in ctx.motors_of(axis):
            vmax = ctx.vars.I(ixx(motor, 16)) * 1000.0  # counts/ms -> counts/s
            if vmax > 0:
                worst = max(worst, d * abs(scale) / t / vmax)
    return t * worst


class ArcMove(Move):
    """A segmented CIRCLE move (Isx13 > 0): a LINEAR-kind move (it blends and stops like
    one) whose XY positions follow its :class:`~motionsim.sim.pmac.buffers.motion.Arc`."""

    __slots__ = ("arc",)

    def __init__(self, n: int, tm: float, ta: float, start: dict[str, float],
                 end: dict[str, float], arc: motion.Arc) -> None:
        super().__init__(n, LINEAR, tm, ta, start, end, None)
        self.arc = arc


def _progress(m: Move, t: float, ta_out: float | None = None) -> tuple[float, float]:
    """How far along its own path ``m`` is at ``t`` (0..1) and how fast (per second): the
    move's share of the blended profile, a path parameter with the same ramps as the axes
    (ramp in from 0 over ``ta_in``, out over ``ta_out`` when stopping or handing over)."""
    if ta_out is None:
        b_end = m.b_end if m.stopping else None
        ta_out = m.ta_out
    else:
        b_end = m.b_end
    v = 1.0 / m.tm if m.tm > 0 else 0.0
    f = motion.position_at(t, 0.0, v, m.b_start, m.ta_in, 0.0, b_end, ta_out)
    if f <= 0.0 or f >= 1.0:
        return (0.0 if f <= 0.0 else 1.0), 0.0
    return f, motion.velocity_at(t, v, m.b_start, m.ta_in, 0.0, b_end, ta_out)


def _arc_offset(m: Move, t: float, ta_out: float | None, out: dict[str, float],
                vel: bool) -> None:
    """Add to ``out`` how far ``m``'s arc is from its chord at ``t`` (position, or its rate
    with ``vel``): the blended chord profile plus this offset puts a segmented CIRCLE's
    commanded positions on the arc (TSRM p177: with Isx13 > 0 the path is computed as points
    on it every Isx13 ms; a blend adds the offsets of both moves, each at its own progress,
    so the path stays continuous through the hand-off) ``[INF]`` for the blend ramps."""
    a = m.arc
    assert a is not None
    f, df = _progress(m, t, ta_out)
    x0, y0 = m.start.get("X", 0.0), m.start.get("Y", 0.0)
    dx, dy = m.end.get("X", x0) - x0, m.end.get("Y", y0) - y0
    if vel:
        if df == 0.0:
            return
        tx, ty = a.tangent(f)
        ox, oy = (tx - dx) * df, (ty - dy) * df
    else:
        px, py = a.point(f)
        ox, oy = px - (x0 + f * dx), py - (y0 + f * dy)
    out["X"] = out.get("X", x0) + ox
    out["Y"] = out.get("Y", y0) + oy


class BlendedProfile(Profile):
    """Constant velocity between ramps centred on the programmed points; the ramp in blends
    from the previous move's velocity, the ramp out (when stopping) goes to rest."""

    kind = LINEAR
    blends = True
    family = "linear"

    def positions(self, m: Move, t: float) -> dict[str, float]:
        out: dict[str, float] = {}
        v, v_prev = m.v, m.v_prev
        b_end = m.b_end if m.stopping else None
        for a in m.end:
            out[a] = motion.position_at(
                t, m.start.get(a, 0.0), v.get(a, 0.0), m.b_start, m.ta_in,
                v_prev.get(a, 0.0), b_end, m.ta_out,
            )  # fmt: skip
        prev = m.prev
        if m.arc is not None:
            _arc_offset(m, t, None, out, False)
        if prev is not None and prev.arc is not None:
            _arc_offset(prev, t, m.ta_in, out, False)
        return out

    def velocities(self, m: Move, t: float) -> dict[str, float]:
        out: dict[str, float] = {}
        v, v_prev = m.v, m.v_prev
        b_end = m.b_end if m.stopping else None
        for a in m.end:
            out[a] = motion.velocity_at(
                t, v.get(a, 0.0), m.b_start, m.ta_in, v_prev.get(a, 0.0), b_end, m.ta_out
            )
        prev = m.prev
        if m.arc is not None:
            _arc_offset(m, t, None, out, True)
        if prev is not None and prev.arc is not None:
            _arc_offset(prev, t, m.ta_in, out, True)
        return out


PROFILE = BlendedProfile()

__all__ = ["PROFILE", "ArcMove", "BlendedProfile", "plan", "velocity_limited"]
