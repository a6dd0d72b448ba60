"""M-variables through their definitions: values read and written in the card's memory.

An M-variable defined ``M1->Y:$078802,8,1`` is bit 8 of the Y word at $078802; its value is
read from, and written into, that word (PSRM p262; TUM p246). Memory is 24-bit X and Y words
plus 48-bit longs (``D``/``L``, and ``DP``/``F``); addresses in the mapping table
(:mod:`motionsim.sim.pmac.card.registers`) show simulated state (motor and CS status, positions).
Several M-variables may point at one word: each sees the others' writes.

Value rules (PUM p154, spec §11.7): integer forms round a written value (half away from
zero) and roll it over into the field's width, no error; ``S`` fields are two's complement;
``L``/``F`` keep floats. ``TW*`` forms read 0 (no thumbwheel hardware) and ignore writes.
Undefined and self-referenced (``->*``) M-variables are plain variables
(:class:`motionsim.sim.pmac.card.variables.Variables` holds their values). Factory state: every
M-variable self-referenced (the TUM's ``M0..8191->*`` reset) ``[INF]``.
"""

from __future__ import annotations

import math

from motionsim.sim.pmac.card.mvar_defs import SELF, TW_KINDS, MDef
from motionsim.sim.pmac.card.registers import Register

_LONG_BITS = 48


def _round(v: float) -> int:
    return int(math.floor(abs(v) + 0.5)) * (1 if v >= 0 else -1)


def _signed(raw: int, bits: int) -> int:
    raw &= (1 << bits) - 1
    return raw - (1 << bits) if raw >> (bits - 1) else raw


class MVariables:
    """Definitions and the memory they point into."""

    def __init__(self) -> None:
        self.defs: dict[int, MDef] = {}
        self.words: dict[tuple[str, int], int] = {}
        self.longs: dict[tuple[str, int], float] = {}
        #: ``{(space, address): Register}`` — set by the controller (mapping table).
        self.registers: dict[tuple[str, int], Register] = {}

    def clear(self) -> None:
        """Factory state: all self-referenced, memory zero."""
        self.defs.clear()
        self.words.clear()
        self.longs.clear()

    # -- definitions ------------------------------------------------------------------------

    def define(self, first: int, last: int, d: MDef) -> None:
        for n in range(first, last + 1):
            if d is SELF or d.kind == "*":
                self.defs.pop(n, None)
            else:
                self.defs[n] = d

    def definition(self, n: int) -> MDef:
        return self.defs.get(n, SELF)

    # -- values -----------------------------------------------------------------------------

    def _word(self, space: str, address: int) -> int:
        reg = self.registers.get((space, address))
        if reg is not None:
            return reg.read() & 0xFFFFFF
        return self.words.get((space, address), 0)

    def read(self, d: MDef) -> float:
        """The value of an M-variable defined ``d`` (not ``*``)."""
        kind = d.kind
        if kind in ("X", "Y"):
            word = self._word(kind, d.address)
            raw = (word >> d.offset) & ((1 << d.width) - 1)
            return float(_signed(raw, d.width) if d.signed else raw)
        if kind in TW_KINDS:
            return 0.0
        reg = self.registers.get(("D", d.address)) if kind == "D" else None
        if reg is not None:
            return float(_signed(reg.read(), _LONG_BITS))
        return self.longs.get((kind, d.address), 0.0)

    def write(self, d: MDef, value: float) -> float:
        """Store ``value`` through ``d``; returns the value the M-variable now holds."""
        kind = d.kind
        if kind in ("X", "Y"):
            mask = (1 << d.width) - 1
            field = _round(value) & mask
            key = (kind, d.address)
            word = (self._word(kind, d.address) & ~(mask << d.offset)) | (field << d.offset)
            reg = self.registers.get(key)
            if reg is None:
                self.words[key] = word & 0xFFFFFF
            elif reg.write is not None:
                reg.write(word & 0xFFFFFF)
            return self.read(d)
        if kind in TW_KINDS:
            return 0.0
        if kind in ("L", "F"):
            self.longs[(kind, d.address)] = float(value)
            return float(value)
        raw = _signed(_round(value), _LONG_BITS if kind == "D" else 32)
        reg = self.registers.get(("D", d.address)) if kind == "D" else None
        if reg is not None:
            if reg.write is not None:
                reg.write(raw)
            return self.read(d)
        self.longs[(kind, d.address)] = float(raw)
        return float(raw)


__all__ = ["MVariables"]
