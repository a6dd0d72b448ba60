"""Bad input to the MC4 language (issue 22 "Bad input"; spec trio.md §11.2–§11.4): each is the
compile error with the program, line and column, and nothing is stored."""

from __future__ import annotations

import pytest
from motionsim.sim.errors import ParseError

from tests.sim.trio.conftest import make

INIT = "estop_in = 7\n"


@pytest.mark.parametrize(("name", "text", "program", "line", "column", "what"), [
    ("P", "x = 1\nDIM SPEED AS INTEGER\n", "P", 2, 5, "SPEED is a Trio BASIC keyword"),
    ("P", "DIM n AS INTEGER\nn = 2\n  DIM n AS FLOAT\n", "P", 3, 3, "DIM twice"),
    ("P", "DIM n(0) AS INTEGER\n", "P", 1, 7, "whole number >= 1"),
    ("P", "VR(0) = n\nDIM n AS INTEGER\n", "P", 2, 1, "DIM comes before the first use"),
    ("P", 'INCLUDE "INIT"\nDIM estop_in AS BOOLEAN\n', "P", 2, 1, "already used as a local"),
    ("P", "DIM n AS REAL\n", "P", 1, 10, "DIM needs a type"),
    ("P", 'VR(0) = 1\n INCLUDE "NOWHERE"\n', "P", 2, 2, "there is no program NOWHERE"),
    ("P", 'INCLUDE "P"\n', "P", 1, 1, "cannot include itself"),
    ("P", 'INCLUDE "NESTED"\n', "NESTED", 2, 1, "nested INCLUDE"),
    ("P", 'INCLUDE "MOVER"\n', "MOVER", 2, 1, "may hold only DIM, GLOBAL, CONSTANT"),
    ("P", "ON BASICERROR\n", "P", 1, 14, "ON BASICERROR needs GOTO"),
    ("P", "ON BASICERROR GOTO\n", "P", 1, 19, "needs the label"),
    ("P", "ON BASICERROR GOTO handler\nVR(0)=1\n", "P", 1, 1, "label 'HANDLER' is not defined"),
    ("P", "DIM s AS STRING\ns = 5\n", "P", 2, 1, "type mismatch"),
    ("P", 'x = "text"\n', "P", 1, 1, "a string needs DIM X AS STRING"),
    ("P", "DIM a(3) AS FLOAT\nVR(0) = a\n", "P", 2, 1, "A is an array"),
    ("P", 'GLOBAL "PI", 10\n', "P", 1, 8, "PI is a Trio BASIC keyword"),
    ("P", 'CONSTANT "limit", VR(3)\n', "P", 1, 19, "CONSTANT needs a number"),
    ("P", "MOVE(1e999)\n", "P", 1, 6, "number 1e999 is out of range"),
])
def test_issue22_bad_input_is_a_compile_error_with_program_line_and_column(
        name, text, program, line, column, what):
    c = make(model="mc4xx")
    c.store_program("INIT", INIT)
    c.store_program("NESTED", 'a = 1\nINCLUDE "INIT"\n')
    c.store_program("MOVER", "a = 1\nMOVE(a)\n")
    before = c.program_names()
    with pytest.raises(ParseError) as err:
        c.store_program(name, text)
    d = err.value.details
    assert (d["program"], d["line"], d["column"]) == (program, line, column)
    assert what in err.value.message
    assert c.program_names() == before  # nothing stored
    assert c.log.last_seq == 0


def test_issue22_an_error_in_an_included_program_says_who_included_it_where():
    c = make(model="mc4xx")
    c.store_program("MOVER", "a = 1\nMOVE(a)\n")
    with pytest.raises(ParseError) as err:
        c.store_program("MAIN", "VR(0) = 0\nINCLUDE \"MOVER\"\n")
    assert err.value.message.startswith('in "MOVER" (INCLUDEd by MAIN line 2): ')
    assert err.value.details["text"] == "MOVE(a)"


def test_issue22_include_and_dim_at_the_command_line_are_refused():
    c = make(model="mc4xx")
    c.store_program("INIT", INIT)
    assert "only allowed in a stored program" in c.terminal('INCLUDE "INIT"').error
    assert "Local variables cannot be used" in c.terminal("DIM i AS INTEGER").error
