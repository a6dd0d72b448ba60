"""PVT (position-velocity-time) moves (TSRM p463, p406; TUM p292; PUM p180; spec §11.1).

``PVT{t}`` enters PVT mode and sets the segment time (the move-time register, I42 = 0: up to
4095.9998 ms in steps of 1/4096 ms, TUM p292 — the same register ``TM`` writes). Each axis
word ``X{pos}:{vel}`` gives the segment's end position (ABS) or distance (INC) and its signed
end velocity in user units per Isx90 ms; no velocity means an end velocity of 0 (TSRM p406).
From the start position and velocity (the end of the previous segment, 0 from rest), the end
position and velocity and the time, each axis follows the one cubic that joins them (a
Hermite segment, TSRM p463); TA, TS and F play no part. Segments abut without a blend ramp,
so N segments take exactly the sum of their times.

``[INF]`` (spec §11.1): an axis not named in a PVT line ends the segment where it is with
velocity 0; a sequence that ends (no next segment, or a non-PVT move next) with a non-zero end
velocity stops at the end point at once (a velocity step; the manuals only warn against it);
a segment time that is not in (0, 4095.9998] ms when the line is calculated is a run-time
error of the coordinate system (a constant one is refused when the line is sent, ERR003).
"""

from __future__ import annotations

from .hermite import rate_weights, weights
from .move import PVT, Move, PlanContext, Profile, RunTimeError

#: The largest segment time of the move-time register with I42 = 0 (ms).
MAX_SEGMENT_MS = 4095.9998
#: Its resolution: 12 fractional bits of a millisecond (TUM p292, "¼ µs").
RESOLUTION_MS = 1 / 4096


class PvtMove(Move):
    """A PVT segment: ``v0`` / ``v1`` are each axis's start / end velocity (user units per
    Isx90 ms) and ``k`` turns them into Hermite tangents (position units over the segment's
    program time), which do not change when the time base stretches the segment."""

    __slots__ = ("v0", "v1", "k")

    def __init__(
        self, n: int, tm: float, start: dict[str, float], end: dict[str, float],
        v0: dict[str, float], v1: dict[str, float], k: float,
    ) -> None:  # fmt: skip
        super().__init__(n, PVT, tm, 0.0, start, end, None)
        self.v0 = v0
        self.v1 = v1
        self.k = k


def segment_ms(ms: float) -> float:
    """The segment time as the move-time register holds it; outside (0, 4095.9998] ms it is
    a run-time error."""
    if not 0 < ms <= MAX_SEGMENT_MS:
        raise RunTimeError(f"PVT segment time {ms:g} ms is outside (0, {MAX_SEGMENT_MS}] ms")
    q = round(ms / RESOLUTION_MS) * RESOLUTION_MS
    return q if q > 0 else RESOLUTION_MS


def plan(
    ctx: PlanContext, n: int, start: dict[str, float], end: dict[str, float],
    v_start: dict[str, float], v_end: dict[str, float],
) -> PvtMove:  # fmt: skip
    """The PVT segment of line ``n``. ``v_start`` / ``v_end``: axis velocities in user units
    per Isx90 ms at the start (the previous segment's end) and the end (the line's words;
    missing axes 0)."""
    t_prog = segment_ms(ctx.feedrate) / 1000.0
    to_s = t_prog * 1000.0 / ctx.isx90_ms  # user units per Isx90 ms -> units per segment
    return PvtMove(n, t_prog * ctx.time_scale, start, end, v_start, v_end, to_s)


def plan_constant(
    n: int, start: dict[str, float], words: tuple[tuple[str, float, float], ...],
    v_start: dict[str, float], t_prog: float, to_s: float, scale: float,
) -> tuple[PvtMove, dict[str, float]]:  # fmt: skip
    """:func:`plan` for an ABS line of constant words (the streamed line's short cut):
    ``words`` are ``(axis, position, velocity)``, ``t_prog`` the checked segment time (s),
    ``to_s`` the velocity factor; returns the segment and its end velocities."""
    end = start.copy()
    v_end = dict.fromkeys(end, 0.0) if len(end) > len(words) else {}
    for axis, pos, vel in words:
        if axis not in start:
            start[axis] = 0.0
        end[axis] = pos
        v_end[axis] = vel
    return PvtMove(n, t_prog * scale, start, end, v_start, v_end, to_s), v_end


def _basis(m: PvtMove, t: float) -> tuple[float, float]:
    span = m.b_end - m.b_start
    s = (t - m.b_start) / span if span > 0 else 1.0
    return (0.0 if s < 0 else 1.0 if s > 1 else s), span


class PvtProfile(Profile):
    """Each axis on its cubic between ``b_start`` and ``b_end``; at rest at the end point
    after it."""

    kind = PVT
    blends = True
    family = "pvt"
    decide_at_end = True
    stop_ramp = False

    def positions(self, m: Move, t: float) -> dict[str, float]:
        assert isinstance(m, PvtMove)
        s, _ = _basis(m, t)
        h00, h10, h01, h11 = weights(s)
        st, v0, v1, k = m.start, m.v0, m.v1, m.k
        return {
            a: h00 * st.get(a, 0.0) + k * (h10 * v0.get(a, 0.0) + h11 * v1.get(a, 0.0)) + h01 * p1
            for a, p1 in m.end.items()
        }

    def velocities(self, m: Move, t: float) -> dict[str, float]:
        assert isinstance(m, PvtMove)
        s, span = _basis(m, t)
        if span <= 0 or (m.stopping and t >= m.b_end):
            return dict.fromkeys(m.end, 0.0)
        g00, g10, g01, g11 = rate_weights(s)
        st, v0, v1, k = m.start, m.v0, m.v1, m.k
        return {
            a: (g00 * st.get(a, 0.0) + k * (g10 * v0.get(a, 0.0) + g11 * v1.get(a, 0.0))
                + g01 * p1) / span
            for a, p1 in m.end.items()
        }


PROFILE = PvtProfile()

__all__ = [
    "MAX_SEGMENT_MS", "PROFILE", "PvtMove", "PvtProfile", "plan", "plan_constant", "segment_ms",
]  # fmt: skip
