"""``PSET{axis}{data}...``: new present axis positions, without motion (TSRM p31, TUM p341,
PSRM p340; spec §11.4).

PSET assigns the given values to the present positions of the named axes; nothing moves. The
motor positions stay where they are: PSET changes the axis offset, the difference between axis
zero and motor zero (PSRM p179-180, ``#n->`` "the starting offset ... can later be changed in
several ways, including the PSET"). It is a lookahead break: the move before it is not blended
into the move after it (it ends in a stop); the move after it is not calculated until the move
before has finished and PSET has executed, then the I11 calculation delay applies.

Modelled as a zero-time step in the calculated-move queue (so it keeps its place between the
moves of the same lines) of kind DWELL — a break that starts from rest and ends at once — whose
end is the new positions. ``[INF]``:

* the values are absolute (``INC`` does not apply: "assigns new values");
* a synchronous M-variable assignment before PSET goes with the next *move* (PSET is neither a
  move nor a DWELL, TUM p250), not with PSET;
* a PSET executes when motion has stopped, at that servo cycle (a PSET calculated with the CS
  at rest: at the RTI that calculated it, without waiting for I11, which is the delay before a
  *move*; the I11 delay then comes before the move after it); the log shows it as a ``pset``
  event (``cs``, ``n``, ``positions``: the axes set and their new values), with no
  ``move_start`` / ``move_end``;
* ``A`` / CTRL-K before it executes discard it with the rest of the lookahead.
"""

from __future__ import annotations

from .move import DWELL, Move


class PsetMove(Move):
    """A calculated PSET: ``values`` are the axes it sets; ``end`` the positions after it."""

    __slots__ = ("values",)

    def __init__(self, n: int, start: dict[str, float], values: dict[str, float]) -> None:
        super().__init__(n, DWELL, 0.0, 0.0, start, {**start, **values}, None)
        self.values = values


def plan(n: int, start: dict[str, float], values: dict[str, float]) -> PsetMove:
    """The PSET of line ``n``, the axes calculated to be at ``start`` before it."""
    return PsetMove(n, start, values)


__all__ = ["PsetMove", "plan"]
