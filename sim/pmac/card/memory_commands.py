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
* L: 48-bit floating point (:mod:`.pmac_float`), ``R`` the value as a variable is reported,
  ``RH`` its twelve hex digits;
* several words: one line, separated by blanks.

``W`` stores its values in consecutive words from ``{address}``. A value written in hex
(``$…``) is the word's bits — ``WL:$B850,$400000000801`` stores that 48-bit float, as the EPICS
driver sends its trajectory points (spec §12.7) — a decimal value is a number (``WL:$B850,2``
stores 2.0; ``WD:`` / ``WX:`` / ``WY:`` integers, negative ones as two's complement) ``[INF]``.
A read-only register (a status word) ignores the write, as an M-variable write to it does.
A write that reaches program memory outside the user buffer (:mod:`.memory_map`) answers
ERR003 and writes nothing; so does a malformed value (the line does not parse).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Final

from ...errors import Conflict
from . import pmac_float
from .mvar_defs import MAX_ADDRESS
from .variables import format_value

if TYPE_CHECKING:
    from .mvars import MVariables

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
    #: Which values were written in hex (``$…``): their bits, not their number.
    raw: tuple[bool, ...] = ()


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
    raw: list[bool] = []
    while p.at("op", ","):
        p.take()
        tok = p.peek()
        value = p.value_const(tok)
        if space in ("X", "Y", "D") and value != int(value):
            raise p.error(f"{space} words hold integers", tok)
        if space == "L" and not math.isfinite(value):
            raise p.error("L words hold finite numbers", tok)
        values.append(value)
        raw.append(tok is not None and tok[1].startswith("$"))
    if not values:
        raise p.error("W needs {address},{value}")
    if address + len(values) - 1 > MAX_ADDRESS:
        raise p.error("the values run past $FFFFFF")
    return MemoryWrite(space, address, tuple(values), tuple(raw))


def read(cmd: MemoryRead, memory: MVariables) -> str:
    """The reply line of ``cmd``."""
    out: list[str] = []
    space = cmd.space
    for address in range(cmd.address, cmd.address + cmd.count):
        if space in ("X", "Y"):
            word = memory.word(space, address)
            out.append(f"{word:06X}" if cmd.hex else str(word))
            continue
        bits = memory.long(address)
        if cmd.hex:
            out.append(f"{bits:012X}")
        elif space == "D":
            out.append(str(bits - (1 << _LONG_BITS) if bits >> (_LONG_BITS - 1) else bits))
        else:
            out.append(format_value(pmac_float.decode(bits)))
    return " ".join(out)


def write(cmd: MemoryWrite, memory: MVariables) -> None:
    """Store ``cmd``'s values.

    Raises:
        Conflict: (ERR003) a word falls in program memory outside the user buffer; nothing
            is written.
    """
    for k in range(len(cmd.values)):
        if not memory.writable(cmd.address + k):
            raise Conflict(
                f"${cmd.address + k:X} is program memory outside the user buffer "
                "(DEFINE UBUFFER): nothing written", pmac_error="ERR003")
    raw = cmd.raw or (False,) * len(cmd.values)
    for k, value in enumerate(cmd.values):
        address = cmd.address + k
        if cmd.space in ("X", "Y"):
            memory.store_word(cmd.space, address, int(value))
        elif cmd.space == "D" or raw[k]:
            memory.store_long(address, int(value))
        else:
            memory.store_long(address, pmac_float.encode(value))


__all__ = ["READ_HEAD", "WRITE_HEAD", "MemoryRead", "MemoryWrite", "parse_read", "parse_write",
           "read", "write"]
