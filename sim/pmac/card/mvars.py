"""M-variables through their definitions: values read and written in the card's memory.

An M-variable defined ``M1->Y:$078802,8,1`` is bit 8 of the Y word at $078802; its value is
read from, and written into, that word (PSRM p262; TUM p246). Memory is 24-bit X and Y words;
a 48-bit ``D`` (fixed point) or ``L`` (floating point, :mod:`.pmac_float`) word at an address is
its X word (high half) and Y word (low half), so ``WL:`` of a long and ``Y:``/``X:`` reads of
its halves see the same bits (spec §12.7). ``DP``/``F`` (DPRAM, 32-bit) keep their own values.
Several M-variables may point at one word: each sees the others' writes.

The memory map (:mod:`.memory_map`) decides what an address is: a mapped register
(:mod:`.registers`, simulated state), a word of the M-variable definition table
($004000 + n: Y half = the target address, X half = type / offset / width / format code,
TUM p246 — writing the Y half re-points M n, the trick the trajectory scan uses, PUM p150),
the user buffer (``DEFINE UBUFFER``), program memory outside it (not writable: the card keeps
its program buffers there, so a write changes nothing), or plain memory.

Value rules (PUM p154, spec §11.7): integer forms round a written value (half away from
zero) and roll it over into the field's width, no error; ``S`` fields are two's complement;
``L`` keeps the 48-bit float's precision (2**-34 relative), ``F`` a Python float.
``TW*`` forms read 0 (no thumbwheel hardware) and ignore writes. Undefined and
self-referenced (``->*``) M-variables are plain variables
(:class:`motionsim.sim.pmac.card.variables.Variables` holds their values). Factory state: every
M-variable self-referenced (the TUM's ``M0..8191->*`` reset) ``[INF]``.
"""

from __future__ import annotations

import math
from dataclasses import replace

from . import memory_map, pmac_float
from .mvar_defs import SELF, TW_KINDS, MDef
from .registers import Register

_LONG_BITS = 48
_WORD = 0xFFFFFF


def _round(v: float) -> int:
    return int(math.floor(abs(v) + 0.5)) * (1 if v >= 0 else -1)


def _signed(raw: int, bits: int) -> int:
    raw &= (1 << bits) - 1
    return raw - (1 << bits) if raw >> (bits - 1) else raw


class MVariables:
    """Definitions and the memory they point into."""

    def __init__(self) -> None:
        self.defs: dict[int, MDef] = {}
        #: L-variable definitions (``L{n}->``): the variables of compiled PLCs, which the PC
        #: compiler resolves to these addresses; motionsim interprets PLCC source, so it
        #: keeps them here (not in card memory, where the card has none) ``[INF]``.
        self.ldefs: dict[int, MDef] = {}
        self.words: dict[tuple[str, int], int] = {}
        self.longs: dict[tuple[str, int], float] = {}  # DP / F words
        #: ``{(space, address): Register}`` — set by the controller (mapping table).
        self.registers: dict[tuple[str, int], Register] = {}
        #: The user buffer ``(first, last)`` address (``DEFINE UBUFFER``) or None.
        self.ubuffer: tuple[int, int] | None = None

    def clear(self) -> None:
        """Factory state: all self-referenced, memory zero, no user buffer."""
        self.defs.clear()
        self.ldefs.clear()
        self.words.clear()
        self.longs.clear()
        self.ubuffer = None

    # -- definitions ------------------------------------------------------------------------

    def define(self, first: int, last: int, d: MDef, kind: str = "M") -> None:
        defs = self.defs if kind == "M" else self.ldefs
        for n in range(first, last + 1):
            if d is SELF or d.kind == "*":
                defs.pop(n, None)
            else:
                defs[n] = d

    def definition(self, n: int) -> MDef:
        return self.defs.get(n, SELF)

    def l_definition(self, n: int) -> MDef:
        """L-variable ``n``'s definition (``*``: none)."""
        return self.ldefs.get(n, SELF)

    # -- words ------------------------------------------------------------------------------

    def writable(self, address: int) -> bool:
        """May a write store anything at ``address``? (not program memory outside the user
        buffer, :mod:`.memory_map`)."""
        return memory_map.writable(address, self.ubuffer)

    def holds(self, space: str, address: int) -> bool:
        """Does the model give the ``space`` (``X``, ``Y`` or ``D`` for a 48-bit long) word at
        ``address`` a meaning: a mapped register, an M-variable definition word, a word an
        M-variable points at, the user buffer, or a word the host or a program wrote? Data
        gathering (:mod:`motionsim.sim.pmac.tasks.gather`) refuses a source that is none of
        these rather than record zeros the card would not have."""
        if (space, address) in self.registers:
            return True
        halves = ("X", "Y") if space == "D" else (space,)
        if space == "D" and any((h, address) in self.registers for h in halves):
            return True
        if 0 <= address - memory_map.MDEF_BASE < memory_map.N_MDEFS:
            return True
        if self.ubuffer is not None and self.ubuffer[0] <= address <= self.ubuffer[1]:
            return True
        if any((h, address) in self.words for h in halves):
            return True
        for d in self.defs.values():
            if d.address == address and (
                d.kind == space or d.kind in ("D", "L") or space == "D"
            ):
                return True
        return False

    def word(self, space: str, address: int) -> int:
        """The 24-bit X or Y word at ``address``."""
        reg = self.registers.get((space, address))
        if reg is not None:
            return reg.read() & _WORD
        n = address - memory_map.MDEF_BASE
        if 0 <= n < memory_map.N_MDEFS:
            return self._definition_word(space, n)
        return self.words.get((space, address), 0)

    def store_word(self, space: str, address: int, word: int) -> None:
        """Write the 24-bit X or Y word at ``address`` (a read-only register, program memory
        and the self-referenced definitions' words keep their value)."""
        word &= _WORD
        reg = self.registers.get((space, address))
        if reg is not None:
            if reg.write is not None:
                reg.write(word)
            return
        n = address - memory_map.MDEF_BASE
        if 0 <= n < memory_map.N_MDEFS:
            self._redefine(space, n, word)
            return
        if memory_map.writable(address, self.ubuffer):
            self.words[(space, address)] = word

    def long(self, address: int) -> int:
        """The 48-bit word at ``address`` (X high, Y low); a mapped ``D`` register if any."""
        reg = self.registers.get(("D", address))
        if reg is not None:
            return reg.read() & pmac_float.MASK48
        return (self.word("X", address) << 24) | self.word("Y", address)

    def store_long(self, address: int, raw: int) -> None:
        raw &= pmac_float.MASK48
        reg = self.registers.get(("D", address))
        if reg is not None:
            if reg.write is not None:
                reg.write(_signed(raw, _LONG_BITS))
            return
        self.store_word("X", address, raw >> 24)
        self.store_word("Y", address, raw & _WORD)

    def _definition_word(self, space: str, n: int) -> int:
        d = self.defs.get(n)
        if d is None:
            return 0
        return d.address & _WORD if space == "Y" else memory_map.type_code(d)

    def _redefine(self, space: str, n: int, word: int) -> None:
        """A definition word written: the Y half re-points M n (type kept), the X half
        re-types it (address kept). Self-referenced M-variables stay so ``[INF]``."""
        d = self.defs.get(n)
        if d is None:
            return
        if space == "Y":
            self.defs[n] = replace(d, address=word)
        else:
            new = memory_map.from_type_code(word, d)
            if new is not None:
                self.defs[n] = new

    # -- values -----------------------------------------------------------------------------

    def read(self, d: MDef) -> float:
        """The value of an M-variable defined ``d`` (not ``*``)."""
        kind = d.kind
        if kind in ("X", "Y"):
            word = self.word(kind, d.address)
            raw = (word >> d.offset) & ((1 << d.width) - 1)
            return float(_signed(raw, d.width) if d.signed else raw)
        if kind == "L":
            return pmac_float.decode(self.long(d.address))
        if kind == "D":
            return float(_signed(self.long(d.address), _LONG_BITS))
        if kind in TW_KINDS:
            return 0.0
        return self.longs.get((kind, d.address), 0.0)

    def write(self, d: MDef, value: float) -> float:
        """Store ``value`` through ``d``; returns the value the M-variable now holds."""
        kind = d.kind
        if kind in ("X", "Y"):
            mask = (1 << d.width) - 1
            field = _round(value) & mask
            word = (self.word(kind, d.address) & ~(mask << d.offset)) | (field << d.offset)
            self.store_word(kind, d.address, word)
            return self.read(d)
        if kind == "L":
            try:
                raw = pmac_float.encode(float(value))
            except ValueError:
                return self.read(d)  # no float word for it: memory unchanged [INF]
            self.store_long(d.address, raw)
            return self.read(d)
        if kind == "D":
            self.store_long(d.address, _round(value))
            return self.read(d)
        if kind in TW_KINDS:
            return 0.0
        if kind == "F":
            self.longs[(kind, d.address)] = float(value)
            return float(value)
        raw = float(_signed(_round(value), 32))
        self.longs[(kind, d.address)] = raw
        return raw


__all__ = ["MVariables"]
