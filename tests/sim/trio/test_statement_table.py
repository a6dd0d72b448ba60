"""The Trio BASIC statement table (sim/trio/language/commands.py, rows at the foot of
sim/trio/language/parser.py): one row per statement, keyword(s) -> parse -> compile, and the
MC4xx / MC6xx language (firmware 2.x, spec trio.md §11) as the base table plus its own rows."""

from __future__ import annotations

import inspect
from dataclasses import dataclass
from typing import Any

import pytest
from motionsim.sim.errors import ParseError
from motionsim.sim.trio.language import statements as s
from motionsim.sim.trio.language.commands import Row
from motionsim.sim.trio.language.compiler import compile_program
from motionsim.sim.trio.language.keywords import MC4_WORDS
from motionsim.sim.trio.language.parser import BASE, MC4, dialect_of, parse_line, parse_program


def _statement_classes() -> set[type[s.Stmt]]:
    return {c for _n, c in inspect.getmembers(s, inspect.isclass)
            if issubclass(c, s.Stmt) and c is not s.Stmt}


def test_every_statement_class_has_its_compile_function_in_the_mc4_table():
    assert set(MC4.compilers) == _statement_classes()


def test_the_mc4_dialect_is_the_base_table_plus_its_declarations():
    """Spec §11.1 / §11.4: INCLUDE, DIM, GLOBAL and CONSTANT came with the MC4 language; so
    did its structured statements (issue 32: SELECT_CASE, EXIT_LOOP, library FUNCTIONs)."""
    assert MC4.rows[:len(BASE.rows)] == BASE.rows
    assert set(MC4.parsers) - set(BASE.parsers) == {
        "INCLUDE", "DIM", "GLOBAL", "CONSTANT", "SELECT_CASE", "CASE", "END_CASE", "EXIT_LOOP",
        "FUNCTION", "ENDFUNC"}
    assert set(MC4.parsers) - set(BASE.parsers) <= MC4_WORDS
    assert (BASE.strings, BASE.bit_access, BASE.arrays, BASE.shifts) == (False,) * 4
    assert (MC4.strings, MC4.bit_access, MC4.arrays, MC4.shifts) == (True,) * 4
    assert BASE.later_words == MC4.keywords == MC4_WORDS
    assert dialect_of("mc4xx") is MC4
    assert dialect_of("mc2xx") is dialect_of("series2") is BASE


def test_a_parsed_program_carries_the_table_that_compiles_it():
    assert parse_program("DIM a AS INTEGER", "mc4xx").dialect is MC4
    assert parse_program("a = 1").dialect is BASE


def test_an_extension_adds_rows_and_cannot_redefine_one():
    with pytest.raises(ValueError, match="PRINT has two rows"):
        BASE.extend("x", [Row(("PRINT",), BASE.parsers["PRINT"], {})])
    with pytest.raises(ValueError, match="Print is compiled by two rows"):
        BASE.extend("x", [Row(("NEWPRINT",), BASE.parsers["PRINT"],
                              {s.Print: BASE.compilers[s.Print]})])


# -- adding a command: one row and its handlers ---------------------------------------------


@dataclass(frozen=True, slots=True)
class Beep(s.Stmt):
    """A made-up command ``BEEP n`` (not Trio BASIC): n beeps."""

    times: s.Expr


def parse_beep(p: Any, ln: int, col: int) -> s.Stmt:
    return Beep(ln, col, p.expr())


def compile_beep(comp: Any, st: Beep) -> None:
    times = comp.num(st.times)

    def op(c: Any) -> None:
        c.beeps.append(times(c))

    comp.emit(op, st)


BEEPING = BASE.extend("beeping", [Row(("BEEP",), parse_beep, {Beep: compile_beep})])


def test_a_new_command_is_one_row_and_its_parse_and_compile_handlers():
    program = parse_program("x = 1\nBEEP 2 + 1", dialect=BEEPING)
    assert [type(st) for st in program.statements] == [s.Assign, Beep]
    code = compile_program(program)

    class Ctx:
        def __init__(self) -> None:
            self.beeps: list[float] = []

    ctx = Ctx()
    code.ops[code.lines.index(2)](ctx)
    assert ctx.beeps == [3.0]
    with pytest.raises(ParseError, match="BEEP"):  # not a command of the real language
        parse_line("BEEP 3")
