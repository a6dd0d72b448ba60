"""DWELL and DELAY (TSRM p429, TUM p341).

``DWELL t`` holds the axes for t ms of real time (not scaled by ``%``) and is a lookahead
break: nothing after it is calculated until it has finished. ``DELAY t`` is a zero-distance
move of t ms (at least Ta), scaled by the time base, calculated through and blended like a
LINEAR move.
"""

from __future__ import annotations

from ..buffers import motion
from .linear import BlendedProfile
from .move import DELAY, DWELL, Move, PlanContext, Profile


def plan_dwell(n: int, ms: float, pos: dict[str, float]) -> Move:
    """``DWELL ms`` at ``pos`` (negative times count as 0)."""
    return Move(n, DWELL, max(0.0, ms) / 1000.0, 0.0, pos, pos, None)


def plan_delay(ctx: PlanContext, n: int, ms: float, pos: dict[str, float]) -> Move:
    """``DELAY ms`` at ``pos``: a blended zero-distance move."""
    tm = motion.clamp_move_time(max(0.0, ms) / 1000.0, ctx.accel_prog_s) * ctx.time_scale
    return Move(n, DELAY, tm, ctx.accel_real_s, pos, pos, None)


class DwellProfile(Profile):
    """The axes stand still at the programmed point."""

    kind = DWELL
    breaks = True
    stop_ramp = False

    def positions(self, m: Move, t: float) -> dict[str, float]:
        return dict(m.end)

    def velocities(self, m: Move, t: float) -> dict[str, float]:
        return dict.fromkeys(m.end, 0.0)


class DelayProfile(BlendedProfile):
    """A blended move of zero distance."""

    kind = DELAY


DWELL_PROFILE = DwellProfile()
DELAY_PROFILE = DelayProfile()

__all__ = ["DELAY_PROFILE", "DWELL_PROFILE", "plan_delay", "plan_dwell"]
