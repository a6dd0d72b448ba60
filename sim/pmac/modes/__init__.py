"""Turbo PMAC move modes (TUM "move modes … LINEAR, RAPID, CIRCLE, PVT, and SPLINE").

One module per mode computes the move's time from the line and the modal state (``plan``)
and answers for its profile (:class:`~motionsim.sim.pmac.modes.move.Profile`): blending,
lookahead breaks, positions and velocities at an instant. The coordinate system's planner
and executor (:mod:`motionsim.sim.pmac.lookahead`) call only this interface.
"""

from __future__ import annotations

from . import dwell, linear, pvt, rapid, spline
from .move import (
    DELAY,
    DWELL,
    LINEAR,
    PVT,
    RAPID,
    SPLINE,
    Move,
    Profile,
    RunTimeError,
)

#: The profile of each move kind, indexed by ``Move.kind``.
PROFILES: tuple[Profile, ...] = (
    linear.PROFILE, dwell.DWELL_PROFILE, dwell.DELAY_PROFILE, rapid.PROFILE, pvt.PROFILE,
    spline.PROFILE,
)  # fmt: skip

assert all(p.kind == k for k, p in enumerate(PROFILES))

#: ``BLENDS[a][b]``: a move of kind ``a`` blends into a following move of kind ``b``.
BLENDS: tuple[tuple[bool, ...], ...] = tuple(
    tuple(a.blends and b.blends and a.family == b.family for b in PROFILES) for a in PROFILES
)

__all__ = [
    "BLENDS", "DELAY", "DWELL", "LINEAR", "PROFILES", "PVT", "RAPID", "SPLINE", "Move",
    "Profile", "RunTimeError",
]  # fmt: skip
