"""What an address of the simulated card's memory is (spec pmac.md §12.7; TUM p246, TSRM p164).

* mapped registers (:mod:`.registers`): motor / CS status, positions, servo counter, task
  times — simulated state;
* $004000–$005FFF: the M-variable definition words of M0 … M8191 (Y = address, X = type
  code) — the definitions themselves;
* $00A000 … $0107FF: open memory (program buffers, and at its top the user buffer) — only
  the user buffer is writable;
* $030000–$03FFFF: extended memory's default user buffer (Option 5x1/5x3, V1.937+) — plain
  memory ``[INF]``;
* everything else (other registers, I/O, DPRAM): plain memory, holding what is written.

``DEFINE UBUFFER {n}`` reserves the top ``n`` words of open memory: end $010800 (standard
memory), so the buffer is ``$010800 − n`` … $0107FF and I4908 reads ``$010800 − n``
(TSRM p164). The start of open memory ($00A000, after the Q-variables) is ``[BK]``; with it a
host write into program memory outside the user buffer answers ERR003 and changes nothing
(the card would overwrite its own programs; the simulator keeps them), and an M-variable
write there is dropped ``[INF]``.

The X half of a definition word: the manual gives no encoding (spec §12.11), so this one is
private ``[INF]``: bits 16–19 the kind, 10–11 the format, 5–9 the width, 0–4 the offset.
Writing it with a code of this form re-types the M-variable; another value changes nothing.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Final

from .mvar_defs import MDef

MDEF_BASE: Final = 0x004000
N_MDEFS: Final = 8192
OPEN_MEMORY_START: Final = 0x00A000
OPEN_MEMORY_END: Final = 0x010800  # one past the last word (standard memory)
EXTENDED_USER: Final = (0x030000, 0x03FFFF)

_KINDS: Final = ("X", "Y", "D", "L", "DP", "F")
_FORMATS: Final = "USDC"


def writable(address: int, ubuffer: tuple[int, int] | None) -> bool:
    """False for program memory outside the user buffer."""
    if OPEN_MEMORY_START <= address < OPEN_MEMORY_END:
        return ubuffer is not None and ubuffer[0] <= address <= ubuffer[1]
    return True


def ubuffer_range(words: int) -> tuple[int, int]:
    """The addresses ``DEFINE UBUFFER words`` reserves."""
    return OPEN_MEMORY_END - words, OPEN_MEMORY_END - 1


def type_code(d: MDef) -> int:
    """The X half of ``d``'s definition word (0 for thumbwheel forms)."""
    if d.kind not in _KINDS:
        return 0
    kind = _KINDS.index(d.kind) + 1
    return (kind << 16) | (_FORMATS.index(d.fmt) << 10) | ((d.width & 0x1F) << 5) | d.offset


def from_type_code(word: int, d: MDef) -> MDef | None:
    """``d`` re-typed by an X-half ``word``, or None if ``word`` is not a code of this form."""
    kind = (word >> 16) & 0xF
    width, offset = (word >> 5) & 0x1F, word & 0x1F
    if word >> 20 or not 1 <= kind <= len(_KINDS) or offset > 23:
        return None
    name = _KINDS[kind - 1]
    if name in ("X", "Y"):
        if width not in (1, 4, 8, 12, 16, 20, 24) or offset + width > 24:
            return None
        return replace(d, kind=name, offset=offset, width=width, fmt=_FORMATS[(word >> 10) & 3])
    return replace(d, kind=name, offset=0, width=48, fmt="U")


__all__ = ["MDEF_BASE", "N_MDEFS", "OPEN_MEMORY_END", "from_type_code", "type_code",
           "ubuffer_range", "writable"]
