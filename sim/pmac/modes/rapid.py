"""RAPID moves: timing and profile.

Each axis moves at Ixx22 counts/ms with Ixx21 ms of acceleration added, the longest axis
setting the time, never blended; motor 1's values are used for every axis ``[INF]`` (the
axis→motor mapping is not modelled). The move is a lookahead break (TUM p341): it starts
from rest, ends in a stop, and nothing after it is calculated until it has finished. The
commanded position runs at constant velocity from start to end.
"""

from __future__ import annotations

from motionsim.sim.pmac import motion
from motionsim.sim.pmac.modes.linear import BlendedProfile
from motionsim.sim.pmac.modes.move import RAPID, Move, PlanContext
from motionsim.sim.pmac.variables import ixx


def plan(ctx: PlanContext, n: int, start: dict[str, float], end: dict[str, float]) -> Move:
    """The RAPID move of line ``n`` from ``start`` to ``end``."""
    vars_ = ctx.vars
    speed = vars_.I(ixx(1, 22)) * 1000.0  # cts/ms -> units/s
    dist = max((abs(end[a] - start[a]) for a in end), default=0.0)
    t = (dist / speed if speed > 0 else 0.0) + vars_.I(ixx(1, 21)) / 1000.0
    t = max(t, motion.MIN_MOVE_S) * ctx.time_scale
    return Move(n, RAPID, t, 0.0, start, end, None)


class RapidProfile(BlendedProfile):
    """From rest to rest at constant velocity (no ramps: ``ta`` is 0)."""

    kind = RAPID
    blends = False
    family = ""
    breaks = True


PROFILE = RapidProfile()

__all__ = ["PROFILE", "RapidProfile", "plan"]
