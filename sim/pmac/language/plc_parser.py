"""Which statements a Turbo PMAC PLC program may hold (TUM p253, p376; TSRM p381, p423-424;
PUM p162).

A PLC line is read by the one parser of the command language (:func:`.parser.parse_line`, the
keyword table), as a motion-program line is; this module keeps only the PLC's own rules on
what comes back:

* assignments ``P1=P1+1``, ``M1=1`` (M-variables are the PLC's I/O), ``I5=3``, ``Q2=P1*3``;
  a synchronous assignment (``M1==1``) belongs to motion programs (ERR003);
* ``IF ({condition})``, ``ELSE``, ``ENDIF``, ``WHILE ({condition})``, ``ENDWHILE``
  (:mod:`.flow_statements`). PLCs have no one-line forms: statements after ``IF (...)``,
  ``WHILE (...)`` or ``ELSE`` on the same line belong to the block, which an ``ENDIF`` /
  ``ENDWHILE`` closes, on that line or a later one (PUM p162 "Single-Line Condition Actions":
  motion programs only; PSRM p313: in a PLC the card "puts the statements on the next
  program line and expects an ENDIF"). The compiler (:mod:`motionsim.sim.pmac.tasks.plc`)
  applies that;
* a line starting ``AND ({condition})`` / ``OR ({condition})`` extends the condition of the
  ``IF`` / ``WHILE`` line just above it (PUM p162 "Multiple-Line Conditions", PLCs only); the
  ``AND`` / ``OR`` must start its line (ERR003);
* ``CMD"..."``, ``SEND"..."``, ``ADDRESS``, ``ENABLE PLC n`` / ``DISABLE PLC n`` and the
  command families of :data:`FAMILY_STATEMENTS`;
* while entering: ``CLEAR`` and ``CLOSE`` (handled by
  :class:`motionsim.sim.pmac.tasks.plc.PlcTable`); ``OPEN`` is ERR007 (a buffer is open);
* motion statements (``X10``, ``DWELL``), ``GOTO`` / ``GOSUB`` / ``CALL`` / ``RETURN`` and the
  other motion-program words are not PLC statements (ERR003).

Errors are :class:`motionsim.sim.errors.ParseError` with the 1-based ``column`` and
``pmac_error`` ``"ERR003"`` (ERR007 for OPEN); nothing is stored from a line that fails.
"""

from __future__ import annotations

from typing import Any

from ...errors import ParseError
from ..card.macro_station import StationCommand
from . import card_words, plc_idioms
from . import flow_statements as fl
from . import plc_statements as plc_st
from . import statements as st
from .axis_definitions import AxisDefinition
from .expressions import MAX_NESTING, too_deep
from .motor_statements import HomeList
from .parser import parse_line
from .ranges import RangeAssign

_ERR = "ERR003"

#: Statements of the command families a PLC program may hold: each runs, when the scan
#: reaches it, through its row of the on-line command table (``host/commands.py``) with the
#: PLC's addressed ``&n`` / ``#n`` (MACRO station ``MSR`` / ``MSW``, range assignments,
#: ``#n->`` axis definitions, ``HOME{list}``).
FAMILY_STATEMENTS = (StationCommand, RangeAssign, AxisDefinition, HomeList)

#: Everything else a PLC line may hold.
PLC_STATEMENTS = (
    st.Assign, st.Message, plc_idioms.Command, plc_idioms.SendText, plc_idioms.Address,
    plc_st.EnablePlc, plc_st.Clear, st.Close, fl.If, fl.Else, fl.EndIf, fl.While, fl.EndWhile,
    fl.CondLine, *FAMILY_STATEMENTS,
)  # fmt: skip
_OPENS = (st.OpenRotary, st.OpenProgram, plc_st.OpenPlc, card_words.OpenKinematic)

PlcStatement = Any


def _error(message: str, column: int, text: str, code: str = _ERR) -> ParseError:
    return ParseError(message, column=column, text=text, pmac_error=code)


def parse_plc_line(text: str) -> list[tuple[Any, int]]:
    """The statements of one PLC line with their 1-based columns, up to and including a
    ``CLOSE`` (what follows it is on-line text).

    Raises:
        ParseError: column, ERR003 (ERR007 for an ``OPEN``).
    """
    deep = too_deep(text)  # conditions parse recursively: bound the nesting first
    if deep is not None:
        raise _error(f"expression nested deeper than {MAX_NESTING} levels (the limit)", deep,
                     text)
    out: list[tuple[Any, int]] = []
    for stmt, start, _ in parse_line(text, open_=True, until_close=True):
        col = start + 1
        if isinstance(stmt, _OPENS):
            # OPEN while a buffer is open: "buffer already in use" (TSRM p381).
            raise _error("a buffer is already open: CLOSE first", col, text, "ERR007")
        if not isinstance(stmt, PLC_STATEMENTS):
            raise _error(f"{type(stmt).__name__} is not a PLC statement", col, text)
        if isinstance(stmt, st.Assign) and stmt.synchronous:
            raise _error("synchronous assignment is for motion programs", col, text)
        if isinstance(stmt, fl.CondLine) and out:
            raise _error(f"{stmt.op} must start its line", col, text)
        out.append((stmt, col))
    return out


__all__ = ["FAMILY_STATEMENTS", "PLC_STATEMENTS", "PlcStatement", "parse_plc_line"]
