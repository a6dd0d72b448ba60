"""Any PLC text parses or raises a positioned ``ParseError``; nothing else escapes."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st
from motionsim.sim.errors import ParseError
from motionsim.sim.pmac.language.plc_parser import parse_plc_line
from motionsim.sim.pmac.tasks.plc import compile_plc

_PIECES = st.sampled_from([
    "IF", "WHILE", "ELSE", "ENDIF", "ENDW", "AND", "OR", "(", ")", "P1", "M2", "=", "!=", ">",
    "!<", "+", "*", "1", "2.5", " ", 'CMD"#1J+"', 'SEND"X"', "ENABLE PLC 1", "DIS PLC 2..3",
    "CLOSE", "CLEAR", "OPEN", "X10", "==", "$FF", ";", "Q", "I5", "-",
])


@settings(max_examples=300, deadline=None)
@given(st.lists(_PIECES, max_size=12).map("".join))
def test_any_line_parses_or_raises_a_positioned_parse_error(text):
    try:
        parse_plc_line(text)
    except ParseError as e:
        assert e.pmac_error in ("ERR003", "ERR007")
        assert e.column is not None and 1 <= e.column <= len(text) + 1


@settings(max_examples=150, deadline=None)
@given(st.lists(st.lists(_PIECES, max_size=6).map("".join), max_size=5).map("\n".join))
def test_any_program_compiles_or_raises_with_its_line(text):
    try:
        compile_plc(text)
    except ParseError as e:
        assert e.line is not None and 1 <= e.line <= max(1, len(text.splitlines()))
