"""Ixx17, the maximum program acceleration of non-segmented LINEAR moves ("Mode 1").

What the manuals say (PSRM p74 Ix17; TUM p276 "acceleration limiting algorithms of Mode 1";
spec §11.3):

* With Isx13 = 0, if a LINEAR move asks a motor for more acceleration than its Ixx17
  (counts/ms²) "given its TA and TS time settings", the acceleration of **all** motors of the
  coordinate system is stretched out in proportion: the path and the shape of every motor's
  velocity profile stay the same, only the ramp gets longer.
* The limit is applied to the blend into the move (the velocity change at the corner: PSRM
  p75's example, ``F10 TA200 TS0 X20 Y20`` then ``X-20 Y20`` at 10 000 counts/unit: X turns
  by 14.14 units/s = 141.4 counts/ms, over 200 ms 0.707 counts/ms², compared with Ix17, and
  TA is lengthened by that ratio) **and** to the deceleration to a stop at the move's end,
  even when it is removed by blending into the next move: each move is calculated as if it
  could be the last (TUM p276 "When Too Effective"). A stop ramp longer than the move time
  makes the move run slower than programmed; short blended segments slow down unless Ixx17
  is above top speed / smallest segment time.
* The calculation ignores feedrate override (PSRM p74: "does not take into account any
  feedrate override value other than 100"): it is done in program time.
* PMAC looks only two moves ahead for it and cannot undo moves already executing, so the
  limit can still be exceeded (PUM p167 "When not Effective Enough").

Modelled here, each ``[INF]`` where the manuals leave it open:

* Peak acceleration of a ramp of total time ``Ta = max(TA, 2·TS)`` with S-curve time TS at
  each end (constant acceleration between) for a velocity change ΔV is ``ΔV / (Ta − TS')``,
  ``TS' = min(TS, Ta/2)``: ``ΔV/TA`` for a trapezoid, ``ΔV/TS`` for a pure S-curve (as a Delta
  Tau forum answer, "Lookahead is not working", 2020, puts it) ``[INF]``. Stretching TA and TS
  by the same factor keeps the shape; the simulator's ramps keep only their length.
* The move being calculated is checked against the previous calculated LINEAR move (the
  corner) and against a stop from its own speed; the previous move is not recalculated
  ``[INF]`` (the manual's recalculation of the two moves ahead is not modelled).
* The move time is the shortest ``T ≥`` the programmed (and Ixx16-limited) time for which the
  stretched ramp still fits, ``Ta' ≤ T`` (the acceleration time is the minimum move time,
  TSRM p188): for a stop-limited move that is the triangle ``T = √(c·D / Ixx17)`` ``[INF]``.
* The stretched ramp is not rounded to whole ms; the blend clipping ``Ta_{i+1} ≤ 2·(TM_i −
  Ta_i/2)`` still applies after it, so a clipped corner can exceed Ixx17 as the manual
  admits ``[INF]``. An axis with no motor, or a motor with Ixx17 ≤ 0, has no limit ``[INF]``.
* The final stop uses the TA/TS in force then (as without the limit), stretched to at least
  the stop ramp this move needs (``Move.ta_stop``) ``[INF]``.

Segmentation mode with the special lookahead active ("Mode 3": Isx13 > 0, ``DEFINE
LOOKAHEAD``, Isx20 > 0; TSRM p98 regime 2; PSRM p74 "robust acceleration control by looking
ahead far enough"): the lookahead knows the moves ahead, so no intermediate stop is assumed.
A move from rest has its ramp stretched as above; every move carries the stop ramp Ixx17
allows, and the executor decides its deceleration to a stop that much earlier (planned
ahead). ``[INF]`` not modelled: the lookahead's slowing ahead of a corner whose blend would
exceed Ixx17 (blends between segmented moves keep their TA), and any limit on CIRCLE moves
(the motor speeds along an arc vary from segment to segment).
"""

from __future__ import annotations

import math
from collections.abc import Mapping

from ..card.variables import ixx
from .move import PlanContext

#: Relative slack of the feasibility test (rounding of the roots).
_EPS = 1e-9


def shape_factor(ta_s: float, ts_s: float) -> float:
    """Peak over mean acceleration of a ramp of total time ``ta_s`` with ``ts_s`` of S-curve at
    each end: ``Ta / (Ta − min(TS, Ta/2))`` (1 for a trapezoid, 2 for a pure S-curve)."""
    if ta_s <= 0:
        return 1.0
    return ta_s / (ta_s - min(ts_s, ta_s / 2))


def _motor_terms(
    ctx: PlanContext, start: Mapping[str, float], end: Mapping[str, float],
    w: Mapping[str, float],
) -> list[tuple[float, float, float]]:  # fmt: skip
    """``(D, W, A)`` per motor of the CS that moves or moved: distance (counts), the previous
    move's velocity (counts/s) and Ixx17 (counts/s²)."""
    out = []
    for axis in set(end) | set(w):
        d = end.get(axis, 0.0) - start.get(axis, end.get(axis, 0.0))
        wv = w.get(axis, 0.0)
        if d == 0 and wv == 0:
            continue
        for motor, scale in ctx.motors_of(axis):
            a = ctx.vars.I(ixx(motor, 17)) * 1e6  # counts/ms² -> counts/s²
            if a > 0:
                out.append((d * scale, wv * scale, a))
    return out


def _need(terms: list[tuple[float, float, float]], c: float, t: float) -> tuple[float, float]:
    """Ramp times Ixx17 needs at move time ``t``: (into the move, stop from it)."""
    into = stop = 0.0
    for d, w, a in terms:
        v = d / t
        stop = max(stop, c * abs(v) / a)
        into = max(into, c * abs(v - w) / a)
    return max(into, stop), stop


def _roots(p: float, q: float, r: float) -> list[float]:
    """Positive roots of ``p·T² + q·T + r`` (p > 0)."""
    disc = q * q - 4 * p * r
    if disc < 0:
        return []
    s = math.sqrt(disc)
    return [x for x in ((-q - s) / (2 * p), (-q + s) / (2 * p)) if x > 0]


def limited(
    ctx: PlanContext, start: Mapping[str, float], end: Mapping[str, float], t: float,
    w: Mapping[str, float] | None, lookahead: bool = False,
) -> tuple[float, float, float]:  # fmt: skip
    """The move time and ramps after Ixx17, all in program seconds: ``(T, Ta, Ta_stop)``.

    ``t`` is the move time so far (programmed, Ixx16-limited), ``w`` the previous calculated
    LINEAR move's axis velocities (units/s, program time; None from rest). ``Ta`` is the
    ramp into the move (at least TA), ``Ta_stop`` the shortest stop ramp (0 = no limit).
    ``lookahead``: segmentation mode with the special lookahead (Mode 3), which knows the
    moves ahead: only a start from rest and the final stop are limited (see the module).
    """
    ta = ctx.accel_prog_s
    terms = _motor_terms(ctx, start, end, w or {})
    if not terms:
        return t, ta, 0.0
    c = shape_factor(ta, ctx.scurve_prog_s)
    t0 = max(t, 1e-9)
    into, stop = _need(terms, c, t0)
    if lookahead and w is not None:
        return t, ta, stop  # blended within the lookahead: the corner is not limited here
    if into > t0:
        # The smallest T >= t0 with (A/c)·T² >= |D| and >= |D − W·T| for every motor: T0 or a
        # root of one of those quadratics (the feasible set is a union of closed intervals).
        cands = []
        for d, w_, a in terms:
            p = a / c
            cands.append(math.sqrt(abs(d) / p))
            cands += _roots(p, w_, -d) + _roots(p, -w_, d)
        for cand in sorted(x for x in cands if x > t0):
            into, stop = _need(terms, c, cand)
            if into <= cand * (1 + _EPS):
                t0 = cand
                break
        t = t0
    return t, max(ta, min(into, t)), stop


__all__ = ["limited", "shape_factor"]
