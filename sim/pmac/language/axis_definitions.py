"""Axis definitions as the SRM writes them (TSRM p268-270; TUM p258; PSRM p179-180; spec §12.5).

``#{n}->{scale}{axis}[{±scale}{axis}...][{±offset}]`` in the addressed coordinate system:

* ``{scale}`` is counts per user unit, any real number, omitted = 1 (``#1->X``,
  ``#6->-29.1X+100000Y``, ``#9->3333.333Z-666.667``); the motor's position is the sum of its
  terms plus the offset (counts). A definition commands no motion: a motor at rest stays
  where it is (the offset change goes into its jog offset) until ``PMATCH`` starts the axes
  from the motors through the equation, offset included (TUM p259) ``[INF]``;
* up to three axes in one definition, all from one triplet **XYZ** or **UVW**; ``A``, ``B``,
  ``C`` only alone; an axis at most once;
* ``#{n}->0`` removes the definition; ``#{n}->I`` makes motor n an inverse-kinematic axis
  (stored and reported, its position then comes from the kinematic programs, which the
  simulator does not run here ``[INF]``);
* ``#{n}->`` reports the definition in the card's form (``-29.1X+100000Y``), ``0`` if none;
  ``#{n}->,`` is the same query: a comma right after the arrow ends it (the EPICS driver's
  batched poll sends ``&1#7->,`` between other items) ``[INF]``;
* ``UNDEFINE`` clears every definition of the addressed CS, ``UNDEFINE ALL`` those of all CSs.

``FRAX({axes})`` picks the feedrate axes of a program's vector-feedrate moves (default X, Y, Z;
``FRAX`` alone = X, Y, Z ``[INF]``).

Bad text is ERR003 with the column of the offending character; nothing changes.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

from ...errors import ParseError
from ..card.variables import format_value

_NUMBER = r"(?:\d+\.?\d*|\.\d+)"
_TERM = re.compile(rf"\s*(?P<sign>[+-])?\s*(?P<scale>{_NUMBER})?\s*(?P<axis>[XYZABCUVW])?",
                   re.IGNORECASE)
_INVERSE = re.compile(r"\s*I(?![A-Za-z0-9])", re.IGNORECASE)
_TRIPLETS = ("XYZ", "UVW")
#: ``#n->,``: the query with the comma the EPICS driver puts after it in a batched poll
#: (``pmacHardwareTurbo::CS_AXIS_MAPPING`` "&%d#%d->,") — the comma ends the query ``[INF]``.
_QUERY_COMMA = re.compile(r"\s*,")


@dataclass(frozen=True, slots=True)
class AxisDef:
    """A parsed definition: ``terms`` ``((axis, counts per unit), ...)``, ``offset`` counts;
    ``inverse`` for ``#n->I``."""

    terms: tuple[tuple[str, float], ...] = ()
    offset: float = 0.0
    inverse: bool = False

    def report(self) -> str:
        """The card's text for ``#n->``: ``1000X``, ``-29.1X+100000Y``, ``2000Z-6000``."""
        if self.inverse:
            return "I"
        out = ""
        for k, (axis, scale) in enumerate(self.terms):
            s = format_value(scale)
            if scale == 1:
                s = ""
            elif scale == -1:
                s = "-"
            if k and not s.startswith("-"):
                s = "+" + s
            out += s + axis
        if self.offset:
            s = format_value(self.offset)
            out += s if s.startswith("-") else "+" + s
        return out or "0"


def _error(message: str, column: int, text: str) -> ParseError:
    return ParseError(message, column=column, text=text, pmac_error="ERR003")


def parse(text: str, pos: int) -> tuple[AxisDef | None, int]:
    """The definition after ``->`` at ``pos`` of ``text``: ``(None, pos)`` for the query
    (nothing follows), ``(AxisDef(), end)`` for ``0``.

    Raises:
        ParseError: column of the bad part, ERR003.
    """
    m = _INVERSE.match(text, pos)
    if m is not None:
        return AxisDef(inverse=True), m.end()
    terms: list[tuple[str, float]] = []
    offset: float | None = None
    end = pos
    while True:
        m = _TERM.match(text, end)
        if m is None or m.end() == end or not (m.group("scale") or m.group("axis")):
            break
        col = m.start() + 1 + (len(m.group()) - len(m.group().lstrip()))
        if terms and m.group("sign") is None:
            break  # a term without + / - starts the next command (``#3->1000X B1``) [INF]
        if offset is not None:
            raise _error("the offset must be the last term", col, text)
        value = float(m.group("scale")) if m.group("scale") else 1.0
        if m.group("sign") == "-":
            value = -value
        axis = m.group("axis")
        if axis is None:
            offset = value
        else:
            axis = axis.upper()
            _check_axis(terms, axis, m.start("axis") + 1, text)
            terms.append((axis, value))
        end = m.end()
    if not terms and offset is None:
        comma = _QUERY_COMMA.match(text, pos)
        return None, comma.end() if comma else pos
    if not terms:
        if offset:
            raise _error("expected an axis letter after the scale factor", end + 1, text)
        return AxisDef(), end
    return AxisDef(tuple(terms), offset or 0.0), end


def _check_axis(terms: list[tuple[str, float]], axis: str, col: int, text: str) -> None:
    if any(a == axis for a, _ in terms):
        raise _error(f"axis {axis} twice in one definition", col, text)
    letters = [a for a, _ in terms] + [axis]
    if len(letters) > 1 and (any(a in "ABC" for a in letters)
                             or not any(set(letters) <= set(t) for t in _TRIPLETS)):
        raise _error("a combined definition takes axes of one triplet, XYZ or UVW "
                     "(A, B, C only alone)", col, text)


@lru_cache(maxsize=256)
def lookup(report: str) -> AxisDef:
    """The definition a stored report text stands for (cached: read every servo query)."""
    d, _ = parse(report, 0)
    return d if d is not None else AxisDef()


@dataclass(frozen=True, slots=True)
class AxisDefinition:
    """``#{motor}->{definition}``; ``definition`` None = the query ``#{motor}->``."""

    motor: int
    definition: AxisDef | None


@dataclass(frozen=True, slots=True)
class Frax:
    """``FRAX({axes})``: the vector-feedrate axes of the program's following moves."""

    axes: tuple[str, ...]


def frax_word(p: Any, tok: tuple[str, str, int, int]) -> Frax:
    """Keyword-table builder: ``FRAX[({axes})]`` (no list: X, Y, Z)."""
    return Frax(p.axis_list() or ("X", "Y", "Z"))


def motor_terms(ctl: Any, motor: int) -> tuple[int, AxisDef] | None:
    """``(cs, definition)`` of ``motor``, or None."""
    have = ctl.motors.get(motor)
    if have is None:
        return None
    return have[0], lookup(have[1])


__all__ = ["AxisDef", "AxisDefinition", "Frax", "frax_word",
           "lookup", "motor_terms", "parse"]
