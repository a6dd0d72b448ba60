"""``LIST`` on-line commands: program listings in the card's format.

Forms (spec pmac.md §11.8; the Turbo SRM LIST pages were not found, §11.12):

* ``LIST PLC n[,start[,len]]`` — PLC 0..31 as entered (:mod:`motionsim.sim.pmac.host.listing`);
* ``LIST PROG n[,start[,len]]`` (``PROGRAM``) — a fixed motion program, through the
  controller's ``program_lines(n)`` when the fixed-program store provides it;
* ``LIST ROT`` (``ROTARY``) — the lines of the addressed CS's rotary buffer not yet
  calculated, without offsets and without the ``RET`` ``[INF]``;
* ``LIST FORWARD`` / ``LIST INVERSE`` ``[,start,len]`` — the addressed CS's kinematic
  programs (:mod:`motionsim.sim.pmac.kinematics`), listed as a PROG is. Every CS has both
  buffers, so an empty one (never written, or cleared) answers no lines and no error
  ``[INF]``: the EPICS driver lists them word by word (``&1 list forward,0,1``,
  ``pmacCSController::listKinematic``) and takes an empty reply as the end, and
  dls-pmacanalyse returns what it has read on a reply with no offset; a start beyond the
  last line of a non-empty one is ERR003 as below;
* ``LIST PLCC n`` — ERR003: a compiled PLC is machine code on the card, with no text to list
  ``[INF]`` (the SRM has no LIST PLCC);
* ``LIST GATHER`` — the gather buffer as 12-hex-digit long words in memory order
  (:meth:`motionsim.sim.pmac.tasks.gather.Gather.listing`; DPC ``gather.py``).

An empty or missing buffer (other than a kinematic one), a start beyond the last line, a PLC
number above 31: ERR003 ``[INF]`` (the end of dls-pmacanalyse's chunked read).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ...errors import Conflict, NotSimulated
from ..kinematics.commands import buffer_key
from ..language.list_words import ListBuffer
from . import listing

if TYPE_CHECKING:
    from ...controller import Port
    from ..controller import PmacController

N_PLCS = 32


def _err(message: str) -> Conflict:
    return Conflict(message, pmac_error="ERR003")


def run(cmd: ListBuffer, ctl: PmacController, port: Port) -> list[str]:
    """The reply lines of ``cmd``.

    Raises:
        Conflict: ERR003 — nothing to list there (see the module docstring).
        NotSimulated: LIST PROG while fixed motion programs are not simulated.
    """
    buffer = cmd.buffer
    if buffer == "ROT":
        rot = ctl.coord_system(port.state["cs"]).rotary
        if rot is None:
            raise _err(f"CS {port.state['cs']} has no rotary buffer")
        entries = listing.entries((line.text for _, line in rot.pending), end=None)
        return listing.window(entries, cmd.start, cmd.length) or []
    if buffer == "GATHER":
        return ctl.gather.listing()
    if buffer in ("FORWARD", "INVERSE"):
        cs = port.state["cs"]
        lines = ctl.programs.programs.get(buffer_key(cs, buffer == "INVERSE")) or ()
        if not lines:
            return []  # an empty kinematic buffer lists nothing (module docstring)
        out = listing.window(listing.entries(line.text for line in lines), cmd.start,
                             cmd.length)
        if out is None:
            raise _err(f"CS {cs} has no {buffer.lower()}-kinematic program to list there")
        return out
    assert cmd.number is not None
    if buffer == "PLC":
        if cmd.number >= N_PLCS:
            raise _err(f"no PLC {cmd.number} (0..{N_PLCS - 1})")
        program = ctl.plcs.plc(cmd.number).program
        source = program.lines if program is not None else ()
    else:
        lines_of = getattr(ctl, "program_lines", None)
        if lines_of is None:
            raise NotSimulated("LIST PROG: fixed motion programs are not simulated",
                               pmac_error="ERR003")
        source = tuple(lines_of(cmd.number) or ())
    plc = buffer == "PLC"
    listed = (listing.stored_entries(source, plc=plc) if type(source) is tuple
              else listing.entries(source, plc=plc))
    out = listing.window(listed, cmd.start, cmd.length) if source else None
    if out is None:
        raise _err(f"{buffer} {cmd.number}: nothing to list there")
    return out


__all__ = ["run"]
