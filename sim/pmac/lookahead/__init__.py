"""A Turbo PMAC coordinate system running its program: planning, execution, time base.

What is modelled, with sources, is in each part's docstring: :mod:`.planning`,
:mod:`.execution`, :mod:`.timebase`, :mod:`.states`; the move modes are
:mod:`motionsim.sim.pmac.modes`.
"""

from __future__ import annotations

from ..modes import Move
from .coord import CoordSystem
from .states import TRANSITIONS

__all__ = ["TRANSITIONS", "CoordSystem", "Move"]
