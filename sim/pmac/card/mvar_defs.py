"""M-variable definitions: ``M{n}->X:$078802,8,1`` and the other Turbo forms, as text.

Forms (PSRM p262, TUM p246, TSRM p357; spec pmac.md §11.7):

* ``X[:]{adr},{off}[,{width}[,{fmt}]]`` / ``Y...`` — a field of a 24-bit X or Y word: ``off``
  0–23 is its least significant bit, ``24`` means the whole word; ``width`` ∈ {1, 4, 8, 12, 16,
  20, 24} (default 1); ``fmt`` U unsigned (default), S signed, D BCD, C complementary BCD;
* ``D:{adr}`` 48-bit fixed point across X and Y, ``L:{adr}`` 48-bit float, ``DP:{adr}`` 32-bit
  fixed, ``F:{adr}`` 32-bit float (DPRAM);
* ``TWD:``, ``TWB:``, ``TWS:``, ``TWR:`` thumbwheel / multiplexed I/O (kept as text, read as 0);
* ``*`` — self-referenced: no address, the M-variable is a plain variable (the reset form).

Reported back (``M{n}->``, ``M{a}..{b}->``) one definition per line in the short form of
I9 bit 0 = 0 (``Y:$78802,8``) or with bit 0 = 1 as a whole statement (``M1->Y:$78802,8``).
A whole word is reported width-only (``X:$78003,24,S``), a one-bit field as ``adr,bit``,
format U never shown (PSRM p253 examples). Addresses in upper-case hex without padding, like
the card's I-variable reports ``[INF]``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Final

WIDTHS: Final = frozenset({1, 4, 8, 12, 16, 20, 24})
FORMATS: Final = frozenset("USDC")
WORD_KINDS: Final = ("X", "Y")
LONG_KINDS: Final = ("D", "L", "DP", "F")
TW_KINDS: Final = ("TWD", "TWB", "TWS", "TWR")
MAX_ADDRESS: Final = 0xFFFFFF

_NUMBER = r"(\$[0-9A-Fa-f]+|\d+)"
_WORD_FORM: Final = re.compile(
    rf"^\s*([XY])\s*:?\s*{_NUMBER}\s*,\s*(\d+)\s*(?:,\s*(\d+)\s*(?:,\s*([A-Za-z])\s*)?)?$"
)
_LONG_FORM: Final = re.compile(rf"^\s*(DP|D|L|F)\s*:?\s*{_NUMBER}\s*$", re.IGNORECASE)
_TW_FORM: Final = re.compile(r"^\s*(TWD|TWB|TWS|TWR)\s*:?\s*([0-9A-Za-z$.,:\s]+?)\s*$",
                             re.IGNORECASE)


class DefinitionError(ValueError):
    """A malformed definition; ``column`` is 1-based within the definition text."""

    def __init__(self, message: str, column: int = 1) -> None:
        super().__init__(message)
        self.column = column


@dataclass(frozen=True, slots=True)
class MDef:
    """One M-variable definition. ``kind`` is X Y D L DP F TWD TWB TWS TWR or ``*``."""

    kind: str
    address: int = 0
    offset: int = 0
    width: int = 24
    fmt: str = "U"
    text: str = ""  # the parameters of a TW* form, as given

    @property
    def signed(self) -> bool:
        return self.fmt == "S"


SELF: Final = MDef("*")


@dataclass(frozen=True, slots=True)
class MDefine:
    """The on-line command ``M{first}[..{last}]->{definition}`` (``kind`` ``"L"``: an
    L-variable definition of compiled PLCs, ``L35->Y:$078802,2,1``, same syntax)."""

    first: int
    last: int
    definition: MDef
    kind: str = "M"


#: Where a definition's text after ``->`` ends: at a blank (``M1->X:$10,8,1 M2->*``); blanks
#: before it are not significant (TSRM p23: ``M0-> Y:$78800,0,1`` as set-up files write it).
DEFINITION_TEXT: Final = re.compile(
    r"[ \t]*(?:\*|(?:TW[DBSR]|DP|[XYDLF])(?=[\s:$0-9])\S*)", re.IGNORECASE)


def _int(token: str) -> int:
    return int(token[1:], 16) if token.startswith("$") else int(token)


def parse(text: str) -> MDef:
    """The definition after ``->`` (``X:$078802,8,1``).

    Raises:
        DefinitionError: not a definition the card accepts (the card answers ERR003).
    """
    s = text.strip()
    if s == "*":
        return SELF
    m = _WORD_FORM.match(s.upper())
    if m:
        kind, adr, off, width, fmt = m.groups()
        address, offset = _int(adr), int(off)
        if address > MAX_ADDRESS:
            raise DefinitionError(f"address {adr} is beyond $FFFFFF", text.find(adr) + 1)
        if offset == 24:  # the whole word: ``,24`` (a format comes as ``,24,S``, below)
            if width is not None:
                raise DefinitionError("a whole-word definition (,24) takes no width")
            return MDef(kind, address, 0, 24, "U")
        if offset > 23:
            raise DefinitionError(f"bit offset {offset} is not 0..24", text.find(off) + 1)
        w = 1 if width is None else int(width)
        if w not in WIDTHS:
            raise DefinitionError(f"width {w} is not one of 1,4,8,12,16,20,24")
        if offset + w > 24:
            raise DefinitionError(f"field {offset},{w} does not fit in a 24-bit word")
        f = (fmt or "U").upper()
        if f not in FORMATS:
            raise DefinitionError(f"format {f!r} is not U, S, D or C")
        return MDef(kind, address, offset, w, f)
    m = re.match(rf"^\s*([XY])\s*:?\s*{_NUMBER}\s*,\s*24\s*,\s*([A-Za-z])\s*$", s.upper())
    if m:
        kind, adr, fmt = m.groups()
        if fmt not in FORMATS:
            raise DefinitionError(f"format {fmt!r} is not U, S, D or C")
        return MDef(kind, _int(adr), 0, 24, fmt)
    m = _LONG_FORM.match(s)
    if m:
        address = _int(m.group(2))
        if address > MAX_ADDRESS:
            raise DefinitionError(f"address {m.group(2)} is beyond $FFFFFF")
        return MDef(m.group(1).upper(), address, 0, 48)
    m = _TW_FORM.match(s)
    if m:
        return MDef(m.group(1).upper(), 0, 0, 0, "U", re.sub(r"\s+", "", m.group(2).upper()))
    raise DefinitionError(f"not an M-variable definition: {text.strip()!r}")


def report(d: MDef) -> str:
    """The definition as the card reports it (short form)."""
    if d.kind == "*":
        return "*"
    if d.kind in TW_KINDS:
        return f"{d.kind}:{d.text}"
    adr = f"${d.address:X}"
    if d.kind in LONG_KINDS:
        return f"{d.kind}:{adr}"
    fmt = "" if d.fmt == "U" else f",{d.fmt}"
    if d.width == 24:
        return f"{d.kind}:{adr},24{fmt}"
    if d.width == 1 and d.fmt == "U":
        return f"{d.kind}:{adr},{d.offset}"
    return f"{d.kind}:{adr},{d.offset},{d.width}{fmt}"


__all__ = ["DEFINITION_TEXT", "SELF", "DefinitionError", "MDef", "MDefine", "parse", "report"]
