"""A Turbo PMAC coordinate system running its program: planning, execution, time base.

What is modelled, with sources, is in each part's docstring: :mod:`.planning`,
:mod:`.execution`, :mod:`.timebase`, :mod:`.states`; the move modes are
:mod:`motionsim.sim.pmac.modes`.
"""

from __future__ import annotations

from motionsim.sim.pmac.lookahead.coord import CoordSystem
from motionsim.sim.pmac.lookahead.states import TRANSITIONS
from motionsim.sim.pmac.modes import Move

__all__ = ["TRANSITIONS", "CoordSystem", "Move"]
