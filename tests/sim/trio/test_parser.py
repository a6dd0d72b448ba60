"""Trio BASIC text -> statements: precedence, the forms of the manual, positioned errors."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from motionsim.sim.errors import NotSimulated, ParseError
from motionsim.sim.trio.language import statements as s
from motionsim.sim.trio.language.compiler import compile_program
from motionsim.sim.trio.language.parser import parse_line, parse_program


def test_move_with_axis_modifier():
    (st_,) = parse_line("MOVE(VR(100+n)) AXIS(1)")
    assert st_ == s.MoveCmd(
        1, 1, "MOVE", (s.VrRef(s.Binary("+", s.Num(100.0), s.Local("N"))),), s.Num(1.0)
    )


def test_parameter_with_axis_modifier_in_a_condition():
    (st_,) = parse_line("IF NTYPE AXIS(0)=0 THEN")
    assert st_ == s.IfBlock(1, 1, s.Binary("=", s.Param("NTYPE", s.Num(0.0)), s.Num(0.0)))


@pytest.mark.parametrize(
    ("text", "tree"),
    [
        ("2+3*4", s.Binary("+", s.Num(2.0), s.Binary("*", s.Num(3.0), s.Num(4.0)))),
        ("2*3^2", s.Binary("*", s.Num(2.0), s.Binary("^", s.Num(3.0), s.Num(2.0)))),
        ("8-2-1", s.Binary("-", s.Binary("-", s.Num(8.0), s.Num(2.0)), s.Num(1.0))),
        # MOD binds less tightly than * but more than +
        (
            "1+5 MOD 2*2",
            s.Binary(
                "+", s.Num(1.0), s.Binary("MOD", s.Num(5.0), s.Binary("*", s.Num(2.0), s.Num(2.0)))
            ),
        ),
        # comparisons above AND / OR
        ("a=1 AND b<2", s.Binary("AND", s.Binary("=", s.Local("A"), s.Num(1.0)),
                                 s.Binary("<", s.Local("B"), s.Num(2.0)))),
        ("NOT a=0", s.Binary("=", s.Unary("NOT", s.Local("A")), s.Num(0.0))),
        ("$FF", s.Num(255.0)),
    ],
)
def test_precedence_of_the_manual(text, tree):
    (st_,) = parse_line(f"x={text}")
    assert st_.value == tree


def test_labels_comments_and_case():
    prog = parse_program("start: ' the top\nmove(1) axis(0) REM comment\n  GoTo start\n")
    assert [type(x).__name__ for x in prog.statements] == ["Label", "MoveCmd", "Goto"]


@pytest.mark.parametrize(
    ("text", "line", "column"),
    [
        ("MOVE(10 AXIS(0)", 1, 9),
        ("VR(1)=1\nVR(2)=\n", 2, 7),
        ("x = 3 +* 4", 1, 8),
        ("PRINT \"abc", 1, 7),
        ("MOVECIRC(1,2)", 1, 9),
        ("DPOS=5", 1, 1),
        ("FOR i=1 10", 1, 9),
        ("a = 1 #", 1, 7),
        ("WAIT FOR", 1, 6),
    ],
)
def test_parse_errors_name_line_and_column(text, line, column):
    with pytest.raises(ParseError) as err:
        parse_program(text)
    assert (err.value.line, err.value.column) == (line, column)
    assert err.value.to_dict()["code"] == "parse_error"


@pytest.mark.parametrize(
    ("text", "line", "column", "message"),
    [
        ("FOR i=1 TO 3\nVR(i)=1\n", 1, 1, "FOR without NEXT"),
        ("NEXT i\n", 1, 1, "NEXT without FOR"),
        ("FOR i=1 TO 3\nNEXT j\n", 2, 1, "NEXT J does not match FOR I"),
        ("IF 1 THEN\nVR(1)=1\n", 1, 1, "IF without ENDIF"),
        ("  ENDIF\n", 1, 3, "ENDIF without IF"),
        ("WHILE 1\n", 1, 1, "WHILE without WEND"),
        ("REPEAT\nWEND\n", 2, 1, "WEND without WHILE"),
        ("GOTO nowhere\n", 1, 1, "label 'NOWHERE' is not defined"),
        ("a:\na:\n", 2, 1, "label 'A' is defined twice"),
        ("IF 1 THEN\nELSE\nELSE\nENDIF\n", 3, 1, "ELSE after ELSE"),
    ],
)
def test_structure_errors_found_before_running(text, line, column, message):
    with pytest.raises(ParseError) as err:
        compile_program(parse_program(text))
    assert (err.value.line, err.value.column, err.value.message) == (line, column, message)


@settings(max_examples=300, deadline=None)
@given(st.text(alphabet="MOVE()AXIS0123456789+-*/=<>:;,?\"' IFTHENVRabc$.\n", max_size=40))
def test_any_text_parses_or_raises_a_positioned_parse_error(text):
    try:
        compile_program(parse_program(text))
    except ParseError as exc:
        assert exc.line is not None and exc.line >= 1
        assert exc.column is not None and exc.column >= 1
    except NotSimulated as exc:  # a valid keyword the simulator does not model (ON, IN ...)
        assert exc.details["line"] >= 1 and exc.details["column"] >= 1
