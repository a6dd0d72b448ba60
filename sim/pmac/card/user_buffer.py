"""``DEFINE UBUFFER``, ``DELETE ALL``: the user buffer and the set-up files' clean slate.

* ``DEFINE UBUFFER {words}`` (``DEF UBUF``) reserves ``{words}`` of user memory at the top of
  open memory (TSRM p164; spec §12.7): ``$010800 − words`` … $0107FF, zeroed, and I4908 (end
  of open memory) reads its first address. Programs reach it through M-variables, hosts with
  ``R``/``W`` (:mod:`.memory_commands`). Refused with ERR003 when a user buffer already
  exists, or a rotary, gather or lookahead buffer exists (they are allocated after it: the
  set-up files write ``DELETE ALL`` first) ``[INF]``, or the size does not fit open memory.
* ``DELETE ALL`` (``DEL ALL``) erases the rotary buffers of every CS, the lookahead buffers,
  the gather buffer and the user buffer, and restores I4908 ``[BK]`` (the Turbo page was not
  retrieved, spec §12.11); motion programs, PLCs and kinematic programs stay. ERR001 while
  any CS runs a program ``[INF]``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from ...errors import Conflict
from . import memory_map
from .factory import default_i

if TYPE_CHECKING:
    from ..controller import PmacController

I_END_OF_OPEN_MEMORY = 4908
MAX_WORDS = memory_map.OPEN_MEMORY_END - memory_map.OPEN_MEMORY_START


def _no_program_running(ctl: PmacController, what: str) -> None:
    running = [c.cs for c in ctl.coord_systems.values() if c.running]
    if running:
        raise Conflict(f"CS {running[0]} is running a program: no {what}", pmac_error="ERR001")


@dataclass(frozen=True, slots=True)
class DefineUbuffer:
    """``DEFINE UBUFFER {words}``."""

    words: int


@dataclass(frozen=True, slots=True)
class DeleteAll:
    """``DELETE ALL``."""


def define(ctl: PmacController, stmt: DefineUbuffer) -> None:
    """``DEFINE UBUFFER {words}``: the user buffer at the top of open memory."""
    mem = ctl.vars.mvars
    if mem.ubuffer is not None:
        raise Conflict("a user buffer exists: DELETE ALL first", pmac_error="ERR003")
    if not 1 <= stmt.words <= MAX_WORDS:
        raise Conflict(f"DEFINE UBUFFER {stmt.words}: 1..{MAX_WORDS} words fit open memory",
                       pmac_error="ERR003")
    if ctl.gather_words is not None or any(
        c.rotary is not None or c.lookahead is not None
        for c in ctl.coord_systems.values()
    ):
        raise Conflict("DEFINE UBUFFER comes before other buffers: DELETE ALL first",
                       pmac_error="ERR003")
    first, last = memory_map.ubuffer_range(stmt.words)
    for key in [k for k in mem.words if first <= k[1] <= last]:
        del mem.words[key]
    mem.ubuffer = (first, last)
    ctl.vars.i[I_END_OF_OPEN_MEMORY] = float(first)  # read-only to hosts, set by the card
    ctl.log.emit("ubuffer", first=first, last=last)


def delete_all(ctl: PmacController) -> None:
    """``DELETE ALL``: every rotary, gather, lookahead and user buffer."""
    _no_program_running(ctl, "DELETE ALL")
    for c in ctl.coord_systems.values():
        if c.rotary is not None:
            ctl.delete_rotary(c.cs)
    ctl.delete_gather()
    for c in ctl.coord_systems.values():
        if c.lookahead is not None:
            ctl.delete_lookahead(c.cs)
    mem = ctl.vars.mvars
    if mem.ubuffer is not None:
        first, last = mem.ubuffer
        for key in [k for k in mem.words if first <= k[1] <= last]:
            del mem.words[key]
        mem.ubuffer = None
    ctl.vars.i[I_END_OF_OPEN_MEMORY] = default_i(I_END_OF_OPEN_MEMORY)
    ctl.log.emit("ubuffer", first=None, last=None)


__all__ = ["DefineUbuffer", "DeleteAll", "define", "delete_all"]
