"""The one place a buffered motion command becomes its :class:`Move`.

A BASIC process (``Context.issue``), the command line and the REST move endpoint
(``TrioController.move``) all build the move here: DATUM(n) is its homing sequence
(:mod:`motionsim.sim.trio.motion.datum`); an SP move captures its base axis' FORCE_SPEED as it
is when the move is issued (:mod:`motionsim.sim.trio.motion.axis`); every other command is a
plain :class:`Move` over the axes it drives. Linked moves (CONNECT, CAM, CAMBOX, MOVELINK)
need the program's TABLE and link axis and are built by the BASIC path alone.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .datum import datum_move
from .moves import Move
from .mtypes import SP_GEOMETRY

if TYPE_CHECKING:
    from ..controller import TrioController


def new_move(ctrl: TrioController, kind: str, axes: tuple[int, ...], args: tuple[float, ...],
             process: int, text: str) -> Move:
    """The move ``kind(args)`` issued by ``process`` on ``axes`` (the first is the base axis);
    DATUM raises :class:`BasicError` for a sequence number it does not know."""
    if kind == "DATUM":
        return datum_move(ctrl, axes[0], args, process, text)
    move = Move(ctrl.buffers.new_id(), kind, axes, args, process, text)
    if kind in SP_GEOMETRY:  # FORCE_SPEED as it is when the SP move is issued
        move.force_speed = ctrl.axes[axes[0]].force_speed
    return move


__all__ = ["new_move"]
