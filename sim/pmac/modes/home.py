"""``HOME{list}`` / ``HOMEZ{list}`` in a motion program: the listed motors' home searches as a
step of the program (TSRM ``HOME`` / ``HOMEZ`` program commands ``[BK]``; spec §0 fact 10).

HOME is a lookahead break, like DWELL and PSET: the move before it ends in a stop, nothing
after it is calculated until it is done. Modelled as a zero-distance step of kind DWELL in
the calculated-move queue (so it keeps its place between the moves of its lines): when its
turn comes (motion at rest) every listed motor starts its home search (``#nHM``, the motor's
own Ixx23 speed and Ixx19-Ixx21 ramps; ``HOMEZ`` is the zero-move homing, done at once), and
the program goes on when the last search has ended (its ``jog`` "end" event), then the I11
delay before the next move. ``[INF]``:

* the axes of the homed motors then stand where the motors are: the axis position takes
  the motor's home displacement (as PSET would assign it), so the next ``ABS`` move is
  measured from the home position;
* a motor of another coordinate system homes too and is waited for;
* ``A`` / CTRL-K before it executes discard it with the rest of the lookahead.
"""

from __future__ import annotations

from .move import DWELL, Move


class HomeMove(Move):
    """A calculated ``HOME{list}`` (``zero``: ``HOMEZ``)."""

    __slots__ = ("motors", "zero")

    def __init__(self, n: int, pos: dict[str, float], motors: tuple[int, ...],
                 zero: bool) -> None:
        super().__init__(n, DWELL, 0.0, 0.0, pos, pos, None)
        self.motors = motors
        self.zero = zero


__all__ = ["HomeMove"]
