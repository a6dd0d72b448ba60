"""On-line kinematics commands: ``OPEN FORWARD`` / ``OPEN INVERSE``, ``PMATCH``, ``UNDEFINE``.

* ``&n OPEN FORWARD`` / ``&n OPEN INVERSE`` (``FWD`` / ``INV``, TSRM p379) open the addressed
  CS's forward- or inverse-kinematic buffer for entry on this port; ``CLEAR``, program lines
  and ``CLOSE`` follow as for a PROG (the lines are held beside the PROGs, one buffer each per
  CS). ERR007 while another buffer is open, ERR001 while any CS runs a program; while it is
  open no program may start (``R`` answers ERR015, as with an open PROG).
* ``PMATCH`` re-computes the addressed CS's axis positions from its motors' positions: with
  Isx50 = 1 and a forward program through it, otherwise by inverting the axis definitions
  (TUM p259, p267); reply: the acknowledgement only ``[INF]``.
* ``UNDEFINE`` clears the addressed CS's axis definitions (``#n->I`` included), ``UNDEFINE
  ALL`` every CS's (TSRM p269–270); ERR001 while the CS (any CS for ALL) runs ``[INF]``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ...errors import Conflict
from ..language.axis_definitions import lookup

if TYPE_CHECKING:
    from ...controller import Port
    from ..controller import PmacController
    from ..language.card_words import OpenKinematic, Undefine

N_CS = 16


def buffer_key(cs: int, inverse: bool) -> int:
    """The key of a kinematic buffer beside the PROGs (negative: no PROG number clashes)."""
    return -(cs + (N_CS if inverse else 0))


def _refuse_while_running(ctl: PmacController, cs: int | None, what: str) -> None:
    running = [c.cs for c in ctl.coord_systems.values() if c.running and cs in (None, c.cs)]
    if running:
        raise Conflict(f"CS {running[0]} is running a program: no {what}", pmac_error="ERR001")


def open_kinematic(ctl: PmacController, stmt: OpenKinematic, port: Port) -> None:
    """``OPEN FORWARD`` / ``OPEN INVERSE``: the addressed CS's kinematic buffer takes the
    lines that follow, from this port."""
    if ctl.buffer_holder is not None or ctl.programs.editing() is not None:
        raise Conflict("a buffer is open: CLOSE it first", pmac_error="ERR007")
    _refuse_while_running(ctl, None, "OPEN FORWARD/INVERSE")
    ctl.programs.open_key(buffer_key(port.state["cs"], stmt.inverse), port)
    ctl.buffer_holder = port


def pmatch(ctl: PmacController, cs: int) -> None:
    """``PMATCH`` in CS ``cs``."""
    _refuse_while_running(ctl, cs, "PMATCH")
    ctl.kinematics.pmatch(cs)


def undefine(ctl: PmacController, stmt: Undefine, cs: int) -> None:
    """``UNDEFINE`` (CS ``cs``) / ``UNDEFINE ALL``: no motion, the motors stay put."""
    which = None if stmt.every_cs else cs
    _refuse_while_running(ctl, which, "UNDEFINE")
    for n in [n for n, (c, _d) in ctl.motors.items() if which in (None, c)]:
        offset = lookup(ctl.motors[n][1]).offset
        del ctl.motors[n]
        ctl.axis_offset_changed(n, -offset)  # no motion: the motor stays put
    ctl.log.emit("undefine", cs=which)


__all__ = ["buffer_key", "open_kinematic", "pmatch", "undefine"]
