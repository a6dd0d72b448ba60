"""Kinematic coordinate systems: ``OPEN FORWARD`` / ``OPEN INVERSE`` subroutines, ``#n->I``
motors, Isx50 (TSRM p181–182, p270, p379; TUM p258–267; spec pmac.md §12.6)."""
