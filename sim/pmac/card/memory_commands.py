"""``R[H]{address}[,{count}]`` and ``W{address},{value}[,{value}...]``: the card's memory
read and written word by word from the host.

``{address}`` is a memory space and a word address: ``X:$1000``, ``Y:$78800``, ``D:$88``,
``L:$1000`` (hex with ``$``, else decimal), 0..$FFFFFF. ``R`` reports the word in decimal,
``RH`` in hex; with a count, that many consecutive words (TSRM on-line commands R / RH / W
``[BK]``: the pages were not found by ``search``, pages corpus "R[H]{address} Report the
contents of memory words Turbo PMAC on-line command", "W{address} Write values to memory").

Memory is the M-variable memory (:mod:`motionsim.sim.pmac.card.mvars`): plain words that hold what
was written, and the mapping table (:mod:`motionsim.sim.pmac.card.registers`) where an address shows
simulated state (motor / CS status, positions). An address the model does not hold reads 0
``[INF]``. Reply formats ``[INF]``:

* X / Y: 24-bit words, ``R`` unsigned decimal, ``RH`` six hex digits (``00A03F``);
* D: 48-bit fixed point, ``R`` signed decimal, ``RH`` twelve hex digits (two's complement);
* L: 48-bit floating point, ``R`` the value as a variable is reported; ``RHL`` answers
  ``not_simulated`` (the card's float bit layout is not modelled);
* several words: one line, separated by blanks.

``W`` stores its values in consecutive words from ``{address}``; a read-only register (a
status word) ignores the write, as an M-variable write to it does. Nothing is written when
any value is malformed (the line does not parse).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Final

from motionsim.sim.errors import NotSimulated
from motionsim.sim.pmac.card.mvar_defs import MAX_ADDRESS, MDef
from motionsim.sim.pmac.card.variables import format_value

if TYPE_CHECKING:
    from motionsim.sim.pmac.card.mvars import MVariables

SPACES: Final = ("X", "Y", "D", "L")
#: Right after ``R``: ``H`` for hex, then the space and ``:`` (``RHX:``, ``RY:``).
READ_HEAD: Final = re.compile(r"(H?)([XYDL]):", re.IGNORECASE)
#: Right after ``W``: the space and ``:`` (``WX:``).
WRITE_HEAD: Final = re.compile(r"([XYDL]):", re.IGNORECASE)
_WORD: Final = 0xFFFFFF
_LONG_BITS: Final = 48


@dataclass(frozen=True, slots=True)
class MemoryRead:
    """``R[H]{space}:{address}[,{count}]``."""

    space: str
    address: int
    count: int = 1
    hex: bool = False


@dataclass(frozen=True, slots=True)
class MemoryWrite:
    """``W{space}:{address},{value}[,{value}...]``."""

    space: str
    address: int
    values: tuple[float, ...]


def _address(p: Any) -> int:
    tok = p.peek()
    n = p.integer()
    if n > MAX_ADDRESS:
        raise p.error("address must be 0..$FFFFFF", tok)
    return n


def parse_read(p: Any, head: re.Match[str]) -> MemoryRead:
    """Read ``R...`` from parser ``p`` (``motionsim.sim.pmac.language.parser._Parser``) after its
    ``READ_HEAD`` match ``head``."""
    space = head.group(2).upper()
    address = _address(p)
    count = 1
    if p.at("op", ","):
        p.take()
        tok = p.peek()
        count = p.integer()
        if count < 1 or address + count - 1 > MAX_ADDRESS:
            raise p.error("count must be at least 1 and stay within $FFFFFF", tok)
    return MemoryRead(space, address, count, bool(head.group(1)))


def parse_write(p: Any, head: re.Match[str]) -> MemoryWrite:
    """Read ``W...`` from parser ``p`` after its ``WRITE_HEAD`` match ``head``."""
    space = head.group(1).upper()
    address = _address(p)
    values: list[float] = []
    while p.at("op", ","):
        p.take()
        tok = p.peek()
        value = p.value_const(tok)
        if space in ("X", "Y") and value != int(value):
            raise p.error(f"{space} words hold integers", tok)
        values.append(value)
    if not values:
        raise p.error("W needs {address},{value}")
    if address + len(values) - 1 > MAX_ADDRESS:
        raise p.error("the values run past $FFFFFF")
    return MemoryWrite(space, address, tuple(values))


def _definition(space: str, address: int) -> MDef:
    if space in ("X", "Y"):
        return MDef(space, address, 0, 24)
    return MDef(space, address)


def read(cmd: MemoryRead, memory: MVariables) -> str:
    """The reply line of ``cmd``.

    Raises:
        NotSimulated: ``RHL`` (the floating-point bit layout is not modelled).
    """
    if cmd.hex and cmd.space == "L":
        raise NotSimulated("RHL: the card's 48-bit floating-point layout is not simulated",
                           pmac_error="ERR003")
    out: list[str] = []
    for address in range(cmd.address, cmd.address + cmd.count):
        value = memory.read(_definition(cmd.space, address))
        if cmd.space in ("X", "Y"):
            out.append(f"{int(value) & _WORD:06X}" if cmd.hex else str(int(value)))
        elif cmd.space == "D":
            raw = int(value)
            out.append(f"{raw & ((1 << _LONG_BITS) - 1):012X}" if cmd.hex else str(raw))
        else:
            out.append(format_value(value))
    return " ".join(out)


def write(cmd: MemoryWrite, memory: MVariables) -> None:
    """Store ``cmd``'s values."""
    for k, value in enumerate(cmd.values):
        memory.write(_definition(cmd.space, cmd.address + k), value)


__all__ = ["READ_HEAD", "WRITE_HEAD", "MemoryRead", "MemoryWrite", "parse_read", "parse_write",
           "read", "write"]
