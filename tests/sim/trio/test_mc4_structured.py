"""Structured MC4xx / MC6xx code (issue 32 item 2): SELECT_CASE / CASE / CASE ELSE / END_CASE,
EXIT_LOOP, the shift operators, and FUNCTION ... ENDFUNC in BASIC libraries called from other
programs.

Sources: the MC4 FUNCTION help as quoted on cnblogs ("TRIO-basic指令--函数FUNCTION": functions
live in a function library for use by any BASIC program, at most 16 parameters, parameters of
one type share it, an optional return type, FUNCTION only within a library, no GOSUB / GOTO in
a library, library functions may call each other); a host tool's program-type table (``.BAL``
= type 12, "BASIC Lib"). SELECT_CASE, EXIT_LOOP and ``<<`` ``>>`` pages were not reachable:
their rules are ``[BK]`` / ``[INF]`` (sim/trio/language/structure.py). Programs run in virtual
time at 100 µs a statement.
"""

from __future__ import annotations

import pytest
from motionsim.sim.errors import InvalidValue, ParseError

from tests.sim.trio.conftest import fields, make, run_to


def mc4():
    return make(model="mc4xx")


def run(c, text: str, name: str = "T", process: int = 1, until: float = 0.5) -> dict:
    c.store_program(name, text)
    c.run_program(name, process)
    run_to(c, c.env.now + until)
    return fields(c, "process", process=process)[-1][1]


def refused(text: str, c=None, name: str = "BAD") -> ParseError:
    c = c or mc4()
    before = c.program_names()
    with pytest.raises(ParseError) as err:
        c.store_program(name, text)
    assert c.program_names() == before
    return err.value


def outputs(c) -> list[tuple[float, int, int]]:
    return [(round(t * 1e6), f["output"], f["value"]) for t, f in fields(c, "output")]


# -- SELECT_CASE --------------------------------------------------------------------------------


STATE_MACHINE = """\
FOR stage = 0 TO 6
  SELECT_CASE stage
    CASE 0
      VR(10 + stage) = 100
    CASE 1, 3
      VR(10 + stage) = 13
    CASE 4 TO 5
      VR(10 + stage) = 45
    CASE ELSE
      VR(10 + stage) = -1
  END_CASE
NEXT stage
"""


def test_select_case_runs_the_first_matching_branch_values_lists_ranges_and_else():
    c = mc4()
    assert "error" not in run(c, STATE_MACHINE)
    assert c.vr[10:17] == [100.0, 13.0, -1.0, 13.0, 45.0, 45.0, -1.0]


def test_select_case_with_no_match_and_no_else_runs_nothing_and_goes_on_after_end_case():
    c = mc4()
    run(c, "x = 7\nSELECT_CASE x\n  CASE 1\n    VR(0) = 1\n  CASE 2\n    VR(0) = 2\nEND_CASE\n"
           "VR(1) = 5\n")
    assert c.vr[:2] == [0.0, 5.0]


def test_select_case_compares_strings_and_evaluates_its_value_once():
    c = mc4()
    run(c, """\
DIM mode AS STRING = "AUTO"
SELECT_CASE mode + ""
  CASE "MANUAL"
    VR(0) = 1
  CASE "JOG", "AUTO"
    VR(0) = 2
END_CASE
n = 0
SELECT_CASE n
  CASE 0
    n = 5
  CASE 5
    VR(1) = 99
END_CASE
VR(2) = n
""")
    assert c.vr[:3] == [2.0, 0.0, 5.0]  # n changed in a branch: the value tested stays 0


def test_each_case_line_tested_costs_a_statement_and_the_jump_to_end_case_none():
    """Timing [INF]: SELECT_CASE, each CASE tested and each statement run cost 100 µs."""
    c = mc4()
    run(c, """\
OP(8, ON)
SELECT_CASE 2
  CASE 1
    OP(9, ON)
  CASE 2
    OP(10, ON)
  CASE 3
    OP(11, ON)
END_CASE
OP(12, ON)
""")
    # OP(8) at 0; SELECT 100; CASE 1 200; CASE 2 300; OP(10) 400; END_CASE jump free: OP(12) 500
    assert outputs(c) == [(0, 8, 1), (400, 10, 1), (500, 12, 1)]


@pytest.mark.parametrize(("text", "line", "column", "message"), [
    ("CASE 1\n", 1, 1, "CASE without SELECT_CASE"),
    ("SELECT_CASE 1\n  VR(0) = 1\n  CASE 1\nEND_CASE\n", 2, 3,
     "only a CASE line may follow SELECT_CASE"),
    ("SELECT_CASE 1\nCASE ELSE\nCASE 2\nEND_CASE\n", 3, 1, "CASE after CASE ELSE"),
    ("SELECT_CASE 1\nCASE 1\n", 1, 1, "SELECT_CASE without END_CASE"),
    ("END_CASE\n", 1, 1, "END_CASE without SELECT_CASE"),
    ('SELECT_CASE 1\nCASE "one"\nEND_CASE\n', 2, 1, "type mismatch"),
    ("SELECT_CASE\n", 1, 12, "SELECT_CASE needs the value"),
    ("SELECT_CASE 1\nCASE\nEND_CASE\n", 2, 5, "CASE needs a value"),
    ("FOR i = 1 TO 2\nSELECT_CASE i\nNEXT i\n", 3, 1, "only a CASE line"),
])
def test_a_bad_select_case_is_a_compile_error_at_its_line(text, line, column, message):
    err = refused(text)
    assert (err.details["line"], err.details["column"]) == (line, column)
    assert message in err.message


# -- EXIT_LOOP ----------------------------------------------------------------------------------


def test_exit_loop_leaves_the_innermost_for_while_or_repeat():
    c = mc4()
    last = run(c, """\
FOR i = 1 TO 100
  IF i = 4 THEN EXIT_LOOP
NEXT i
VR(0) = i
n = 0
WHILE TRUE
  n = n + 1
  IF n >= 6 THEN
    EXIT_LOOP
  ENDIF
WEND
VR(1) = n
REPEAT
  m = m + 2
  SELECT_CASE m
    CASE 6
      EXIT_LOOP
  END_CASE
UNTIL m > 100
VR(2) = m
FOR a = 1 TO 3
  FOR b = 1 TO 10
    IF b = 2 THEN EXIT_LOOP
    hits = hits + 1
  NEXT b
NEXT a
VR(3) = hits : VR(4) = a
""")
    assert "error" not in last
    assert c.vr[:5] == [4.0, 6.0, 6.0, 3.0, 4.0]  # the inner FOR exits, the outer runs out


@pytest.mark.parametrize(("text", "line"), [("EXIT_LOOP\n", 1),
                                            ("IF 1 THEN\n  EXIT_LOOP\nENDIF\n", 2)])
def test_exit_loop_outside_a_loop_is_a_compile_error(text, line):
    err = refused(text)
    assert err.details["line"] == line
    assert "EXIT_LOOP outside a loop" in err.message


# -- << and >> ----------------------------------------------------------------------------------


def test_shift_operators_shift_the_integer_part_and_bind_below_plus_and_above_compare():
    c = mc4()
    assert "error" not in run(c, """\
VR(0) = 1 << 4
VR(1) = $F0 >> 4
VR(2) = 1 << 2 + 1
VR(3) = $FF >> 4 = 15
VR(4) = -16 >> 2
VR(5) = (1 << 40) >> 38
bits = 0 : bits = bits OR (1 << 3)
VR(6) = bits
""")
    assert c.vr[:7] == [16.0, 15.0, 8.0, -1.0, -4.0, 4.0, 8.0]


def test_a_shift_by_a_negative_count_is_a_run_time_error():
    c = mc4()
    last = run(c, "n = -1\nVR(0) = 1 << n\n")
    assert last["line"] == 2 and "shift by -1 bits" in last["error"]


@pytest.mark.parametrize("model", ["series2", "mc2xx"])
def test_shifts_and_the_structured_words_are_mc4_language(model):
    c = make(model=model)
    err = refused("VR(0) = 1 << 2\n", c)
    assert (err.details["line"], err.details["column"]) == (1, 11)
    assert "came with the MC4xx / MC6xx language" in err.message
    err = refused("SELECT_CASE 1\n", c)
    assert "SELECT_CASE is not Trio BASIC on the" in err.message


# -- FUNCTION in a BASIC library ------------------------------------------------------------------


MATHLIB = """\
' MATHLIB.BAL: functions for every program
FUNCTION clamp(v, lo, hi AS FLOAT) AS FLOAT
  IF v < lo THEN RETURN lo
  IF v > hi THEN RETURN hi
  RETURN v
ENDFUNC

FUNCTION fact(n AS INTEGER) AS INTEGER
  IF n <= 1 THEN
    RETURN 1
  ENDIF
  RETURN n * fact(n - 1)
ENDFUNC

FUNCTION scaled(counts AS INTEGER) AS FLOAT
  tmp = counts / 4
  RETURN tmp
ENDFUNC

FUNCTION state_name(code AS INTEGER) AS STRING
  SELECT_CASE code
    CASE 0
      RETURN "INIT"
    CASE 1 TO 2
      RETURN "SAFEOP"
    CASE ELSE
      RETURN "OP"
  END_CASE
ENDFUNC

FUNCTION store(index AS INTEGER, value AS FLOAT)
  VR(index) = value
ENDFUNC

FUNCTION next_id() AS INTEGER
  VR(99) = VR(99) + 1
  RETURN VR(99)
ENDFUNC
"""


def test_library_functions_are_called_from_programs_in_expressions_and_as_statements():
    c = mc4()
    c.store_program("MATHLIB", MATHLIB)
    last = run(c, """\
DIM label AS STRING
tmp = 5
VR(0) = clamp(12, 0, 10) + clamp(-3, 0, 10)
VR(1) = fact(5)
VR(2) = scaled(10.9)
VR(3) = tmp
store(4, 2.5)
label = state_name(1) + "/" + state_name(3)
PRINT label
VR(5) = next_id() + next_id
""", name="MAIN")
    assert "error" not in last
    assert c.vr[:6] == [10.0, 120.0, 2.5, 5.0, 2.5, 3.0]
    # scaled(10.9): the INTEGER parameter holds 10; tmp is the function's, MAIN's stays 5
    assert c.unread_output("t") == ["SAFEOP/OP"]


def test_library_functions_serve_every_program_and_process_and_the_command_line():
    c = mc4()
    c.store_program("MATHLIB", MATHLIB)
    c.store_program("A", "VR(10) = fact(3)\n")
    c.store_program("B", "VR(11) = clamp(VR(10) * 2, 0, 10)\n")
    c.run_program("A", 1)
    run_to(c, 0.01)
    c.run_program("B", 2)
    run_to(c, 0.02)
    assert c.vr[10:12] == [6.0, 10.0]
    assert c.terminal("? fact(6)").reply == "720.0000"


def test_a_call_takes_no_time_of_its_own():
    """[INF]: the calling statement costs its 100 µs, the function's statements nothing."""
    c = mc4()
    c.store_program("MATHLIB", MATHLIB)
    run(c, "OP(8, ON)\nVR(0) = fact(10)\nOP(9, ON)\n")
    assert outputs(c) == [(0, 8, 1), (200, 9, 1)]
    assert c.vr[0] == 3628800.0


def test_storing_the_library_again_compiles_its_callers_with_the_new_functions():
    c = mc4()
    c.store_program("MATHLIB", MATHLIB)
    c.store_program("MAIN", "VR(0) = fact(3)\n")
    c.store_program("MATHLIB", MATHLIB.replace("RETURN n * fact(n - 1)", "RETURN 0"))
    run(c, "RUN \"MAIN\", 2\n")
    run_to(c, c.env.now + 0.1)
    assert c.vr[0] == 0.0


def test_a_new_library_that_breaks_a_caller_is_refused_and_changes_nothing():
    c = mc4()
    c.store_program("MATHLIB", MATHLIB)
    c.store_program("MAIN", "VR(0) = clamp(1, 2, 3)\n")
    err = refused(MATHLIB.replace("FUNCTION clamp(v, lo, hi AS FLOAT)", "FUNCTION clamp(v)"),
                  c, name="MATHLIB")
    assert (err.details["program"], err.details["line"]) == ("MAIN", 1)
    assert "CLAMP takes 1 argument, got 3" in err.message
    assert c.program("MATHLIB") == MATHLIB


def test_a_library_cannot_be_run():
    c = mc4()
    c.store_program("MATHLIB", MATHLIB)
    with pytest.raises(InvalidValue, match="MATHLIB is a BASIC library"):
        c.run_program("MATHLIB", 1)


def test_a_run_time_error_in_a_function_stops_the_caller_naming_the_function_and_its_line():
    c = mc4()
    c.store_program("LIB", "FUNCTION ratio(a, b AS FLOAT) AS FLOAT\n  r = a / b\n"
                           "  RETURN r\nENDFUNC\n")
    last = run(c, "VR(0) = 1\nVR(1) = ratio(1, 0)\nVR(2) = 1\n")
    assert last["state"] == "stopped" and last["line"] == 2
    assert "Divide by zero (in FUNCTION RATIO, LIB line 2)" in last["error"]
    assert c.vr[:3] == [1.0, 0.0, 0.0]


def test_waiting_inside_a_function_at_the_command_line_is_an_error_saying_it_is_not_simulated():
    c = mc4()
    c.store_program("LIB", "FUNCTION pause_ms(t AS INTEGER)\n  WA(t)\nENDFUNC\n")
    reply = c.terminal("pause_ms(10)")
    assert "WA inside a FUNCTION would wait: waiting in a library function is not simulated" \
        in reply.error
    assert "FUNCTION PAUSE_MS, LIB line 2" in reply.error


def test_a_function_recursing_without_end_is_a_run_time_error_not_a_hang():
    c = mc4()
    c.store_program("LIB", "FUNCTION deep(n AS INTEGER) AS INTEGER\n  RETURN deep(n + 1)\n"
                           "ENDFUNC\n")
    last = run(c, "VR(0) = deep(0)\n")
    assert "Stack overflow: FUNCTION calls nested deeper than 64" in last["error"]


@pytest.mark.parametrize(("library", "line", "column", "message"), [
    ("x = 1\nFUNCTION f()\nENDFUNC\n", 1, 1, "this statement is outside a FUNCTION"),
    ("FUNCTION f()\n  GOTO there\nENDFUNC\n", 2, 3, "GOTO is not supported in a BASIC library"),
    ("FUNCTION f()\n  GOSUB there\nENDFUNC\n", 2, 3, "GOSUB is not supported"),
    ("FUNCTION f()\n", 1, 1, "FUNCTION F without ENDFUNC"),
    ("FUNCTION f()\nFUNCTION g()\nENDFUNC\n", 2, 1, "FUNCTION inside FUNCTION F"),
    ("FUNCTION f()\nENDFUNC\nFUNCTION f()\nENDFUNC\n", 3, 1, "FUNCTION F is defined twice"),
    ("FUNCTION f()\nENDFUNC\nENDFUNC\n", 3, 1, "ENDFUNC without FUNCTION"),
    ("FUNCTION f() AS INTEGER\n  RETURN \"x\"\nENDFUNC\n", 2, 3, "returns a number"),
    ("FUNCTION f()\n  RETURN 3\nENDFUNC\n", 2, 3, "returns no value (no AS type)"),
    ("FUNCTION f(a AS WORD)\nENDFUNC\n", 1, 17, "expected a type"),
    ("FUNCTION f(a, a AS FLOAT)\nENDFUNC\n", 1, 15, "parameter A is named twice"),
    ("FUNCTION f(" + ", ".join(f"p{i}" for i in range(17)) + ")\nENDFUNC\n", 1, 82,
     "at most 16 parameters"),
    ("FUNCTION speed()\nENDFUNC\n", 1, 10, "SPEED is a Trio BASIC keyword"),
])
def test_a_bad_library_is_a_compile_error_at_its_place(library, line, column, message):
    err = refused(library, name="LIB")
    assert (err.details["line"], err.details["column"]) == (line, column)
    assert message in err.message


@pytest.mark.parametrize(("caller", "line", "column", "message"), [
    ("VR(0) = clamp(1, 2)\n", 1, 1, "CLAMP takes 3 arguments, got 2"),
    ('VR(0) = fact("x")\n', 1, 1, "argument N of FACT needs a number"),
    ("VR(0) = store(1, 2)\n", 1, 1, "STORE returns no value"),
    ("VR(0) = 1\nnot_there(1)\n", 2, 1, "no stored BASIC library has a FUNCTION NOT_THERE"),
    ("VR(0) = missing(2)\n", 1, 1, "nor a FUNCTION of a stored BASIC library"),
    ("RETURN 5\n", 1, 1, "RETURN with a value is only allowed in a FUNCTION"),
    ("FUNCTION g()\nENDFUNC\nVR(0) = 1\n", 3, 1, "this statement is outside a FUNCTION"),
    ("IF 1 THEN FUNCTION g\n", 1, 11, "FUNCTION may be used only within a BASIC library"),
    ("FUNCTION fact(n AS INTEGER)\nENDFUNC\n", 1, 1, "already defined in library MATHLIB"),
])
def test_a_bad_call_or_function_outside_a_library_is_a_compile_error(caller, line, column,
                                                                     message):
    c = mc4()
    c.store_program("MATHLIB", MATHLIB)
    err = refused(caller, c)
    assert (err.details["line"], err.details["column"]) == (line, column)
    assert message in err.message


def test_a_caller_stored_before_its_library_is_refused_and_accepted_after():
    c = mc4()
    refused("VR(0) = fact(3)\n", c, name="MAIN")
    c.store_program("MATHLIB", MATHLIB)
    assert "error" not in run(c, "VR(0) = fact(3)\n", name="MAIN")
    assert c.vr[0] == 6.0


def test_calls_and_return_stand_before_else_in_a_one_line_if():
    c = mc4()
    c.store_program("LIB", "FUNCTION mark(n AS INTEGER)\n  VR(n) = 1\nENDFUNC\n"
                           "FUNCTION pick(a AS INTEGER) AS INTEGER\n"
                           "  IF a > 2 THEN RETURN 5 ELSE RETURN 6\nENDFUNC\n")
    last = run(c, """\
GOSUB sub
IF 1 THEN mark(3) ELSE mark(4)
IF 0 THEN mark(5) ELSE mark(6)
VR(7) = pick(3) * 10 + pick(1)
STOP
sub:
  IF 1 THEN RETURN ELSE VR(9) = 1
""")
    assert "error" not in last
    assert c.vr[3:10] == [1.0, 0.0, 0.0, 1.0, 56.0, 0.0, 0.0]
