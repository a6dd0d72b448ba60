"""``DEFINE COMP`` / ``DELETE COMP``: leadscrew (position) compensation tables, stored with the
entries that follow them (TSRM p302-303; PSRM p207-210).

* ``DEFINE COMP {entries},[#{source}[D],[#{target},]]{count length}`` (one-dimensional) and
  ``DEFINE COMP {rows}.{columns},#{row motor}[D],[#{column motor}[D],[#{target},]]{row
  span},{column span}`` (two-dimensional) define a table belonging to the addressed motor.
  "The next {entries} constants sent ... will be placed into this table" — for a 2D table
  (rows+1)·(columns+1)−1 of them — "as constants separated by spaces and/or carriage
  returns" in 1/16 count, integers. While a table is filling, the constants a port sends are
  its entries (PUM p150: a bare constant is P0= "unless a special table buffer such as a
  compensation table ... has been defined but not filled – in that case, the constant value
  will be entered into the table"); a line that is not all integer constants answers ERR003
  and changes nothing ``[INF]``.
* Refused with ERR003 "if any COMP buffer exists for a lower numbered motor, or if any
  TCOMP, BLCOMP, TBUF, ROTARY, LOOKAHEAD, or GATHER buffer exists" (TSRM p303); a motor
  "can only have one table that belongs to it" (a second DEFINE COMP is ERR003 ``[INF]``).
* ``DELETE COMP`` erases the addressed motor's table (from low-numbered motors up: a table of
  a lower-numbered motor existing is ERR003 ``[INF]``, the mirror of the define rule).
* Not simulated: the correction itself (I51 = 1 enables the tables on the card); a table is
  stored and holds its entries, the motors move as without it. ``LIST COMP`` is not
  simulated either.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Final

from ...errors import Conflict, InvalidValue

if TYPE_CHECKING:
    from ..controller import PmacController

#: The port-state key of the table a port is filling (its owning motor).
FILLING: Final = "comp_filling"
_ENTRY = re.compile(r"[+-]?\d+")


@dataclass(frozen=True, slots=True)
class DefineComp:
    """``DEFINE COMP``: ``rows`` (1D: the entries) and ``columns`` (2D, else None), the
    motors given (``#n``, with ``D`` for the desired position) and the spans in counts."""

    rows: int
    columns: int | None
    motors: tuple[tuple[int, bool], ...]
    spans: tuple[int, ...]

    @property
    def entries(self) -> int:
        """How many constants follow (TSRM p303; PSRM p210: (rows+1)(columns+1)-1)."""
        if self.columns is None:
            return self.rows
        return (self.rows + 1) * (self.columns + 1) - 1


@dataclass(frozen=True, slots=True)
class DeleteComp:
    """``DELETE COMP``: the addressed motor's table."""


@dataclass(slots=True)
class CompTable:
    """A stored table: its definition and the entries received so far (1/16 count)."""

    definition: DefineComp
    values: list[int] = field(default_factory=list)

    @property
    def full(self) -> bool:
        return len(self.values) >= self.definition.entries


def parse_define(p: Any) -> DefineComp:
    """After ``DEFINE COMP``: the size, motors and spans (the parser ``p`` after the object
    word)."""
    tok = p.peek()
    if tok is None or tok[0] != "num":
        raise p.error("DEFINE COMP needs {entries},[#{source}[D],[#{target},]]{count length}")
    p.i += 1
    size = tok[1]
    rows_s, _, cols_s = size.partition(".")
    if not rows_s.isdigit() or (cols_s and not cols_s.isdigit()) or int(rows_s) < 1:
        raise p.error("DEFINE COMP: the size is {entries} or {rows}.{columns}", tok)
    rows, columns = int(rows_s), (int(cols_s) if cols_s else None)
    motors: list[tuple[int, bool]] = []
    spans: list[int] = []
    while p.at("op", ","):
        p.take()
        if p.at("op", "#"):
            p.take()
            m_tok = p.peek()
            n = p.integer()
            if not 1 <= n <= 32 or spans:
                raise p.error(f"DEFINE COMP: no motor {n} here (1..32)", m_tok)
            desired = p.at("word", "D")
            if desired:
                p.take()
            motors.append((n, desired))
            continue
        spans.append(p.integer())
    want = 1 if columns is None else 2
    if len(spans) != want or len(motors) > 3 or (columns is None and len(motors) > 2):
        raise p.error(f"DEFINE COMP: expected {want} span(s) after the motors")
    if columns is not None and not motors:
        raise p.error("DEFINE COMP {rows}.{columns} needs #{row motor}")
    return DefineComp(rows, columns, tuple(motors), tuple(spans))


def _blocking(ctl: PmacController) -> str | None:
    if ctl.gather_words is not None:
        return "a gather buffer exists"
    for c in ctl.coord_systems.values():
        if c.rotary is not None:
            return f"a rotary buffer exists (CS {c.cs})"
        if c.lookahead is not None:
            return f"a lookahead buffer exists (CS {c.cs})"
    return None


def define(ctl: PmacController, stmt: DefineComp, motor: int, state: dict[str, Any]) -> None:
    """``DEFINE COMP`` for ``motor`` (the addressed one); the port (``state``) then fills it."""
    why = _blocking(ctl)
    tables = ctl.comp_tables
    if why is None and any(n < motor for n in tables):
        why = "a table of a lower-numbered motor exists (define from high to low)"
    if why is None and motor in tables:
        why = f"motor {motor} has a table already"
    if why is not None:
        raise Conflict(f"DEFINE COMP: {why}", pmac_error="ERR003")
    tables[motor] = CompTable(stmt)
    state[FILLING] = motor


def delete(ctl: PmacController, motor: int, state: dict[str, Any]) -> None:
    """``DELETE COMP`` of ``motor``."""
    tables = ctl.comp_tables
    if motor not in tables:
        return
    if any(n < motor for n in tables):
        raise Conflict("DELETE COMP: a table of a lower-numbered motor exists (delete from "
                       "low to high)", pmac_error="ERR003")
    del tables[motor]
    if state.get(FILLING) == motor:
        del state[FILLING]


def fill(ctl: PmacController, state: dict[str, Any], text: str) -> None:
    """A line sent while a table fills: its integer constants are the next entries.

    Raises:
        InvalidValue: ERR003 -- a word of the line is not an integer constant (nothing kept).
    """
    motor = state[FILLING]
    table = ctl.comp_tables.get(motor)
    if table is None:
        del state[FILLING]
        return
    words = text.replace(",", " ").split()
    bad = next((w for w in words if not _ENTRY.fullmatch(w)), None)
    if bad is not None:
        raise InvalidValue(
            f"DEFINE COMP (motor {motor}): entry {len(table.values) + 1} of "
            f"{table.definition.entries} must be an integer constant (1/16 count), not {bad!r}",
            pmac_error="ERR003")
    room = table.definition.entries - len(table.values)
    table.values.extend(int(w) for w in words[:room])
    if table.full:
        del state[FILLING]


__all__ = ["FILLING", "CompTable", "DefineComp", "DeleteComp", "define", "delete", "fill",
           "parse_define"]
