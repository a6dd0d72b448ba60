"""Library functions that wait (issue 32): a FUNCTION runs in the calling process, so a
statement in it that waits (WA, WAIT UNTIL / IDLE, a move into a full process buffer) makes
that process wait, then the function goes on and returns its value to the calling expression.

Sources: the MC4 FUNCTION help (quoted on cnblogs, "TRIO-basic指令--函数FUNCTION"): a function
"can take any BASIC commands provided that they work in the context of the required function
operation", is used by any BASIC program of the multi-tasking system, and library functions may
call each other; WA (TJ1P-… WA help: wait the given milliseconds), WAIT UNTIL (re-tested each
servo period, spec §1.6), the process buffer (M206-320: a move waits at its line while the
buffer is full). How the wait is simulated (the statement runs again, calls already returned
answering their values) is sim/trio/language/functions.py ``[INF]``. Virtual time: 100 µs a
statement, 1 ms servo period; a function's own statements take no time.
"""

from __future__ import annotations

from motionsim.sim.trio.language.compiler import compile_program
from motionsim.sim.trio.language.functions import call_site
from motionsim.sim.trio.language.parser import parse_program

from tests.sim.trio.conftest import fields, make, run_to

LIB = """\
FUNCTION pause_ms(t AS INTEGER) AS INTEGER
  VR(50) = VR(50) + 1
  WA(t)
  RETURN t * 2
ENDFUNC
FUNCTION twice(t AS INTEGER) AS INTEGER
  x = pause_ms(t) + pause_ms(t)
  RETURN x + 1
ENDFUNC
FUNCTION settle(limit AS FLOAT) AS FLOAT
  count = 0
  WAIT UNTIL VR(60) > limit
  count = VR(60)
  RETURN count
ENDFUNC
FUNCTION go(d AS FLOAT) AS INTEGER
  MOVE(d) AXIS(0)
  RETURN PMOVE
ENDFUNC
"""


def controller():
    c = make(model="mc4xx")
    c.store_program("LIB", LIB)
    return c


def run(c, text: str, until: float = 1.0) -> dict:
    c.store_program("T", text)
    c.run_program("T", 1)
    run_to(c, until)
    return fields(c, "process", process=1)[-1][1]


def outputs(c) -> list[tuple[int, int]]:
    """(µs, output) of each OP switched on."""
    return [(round(t * 1e6), f["output"]) for t, f in fields(c, "output") if f["value"]]


def test_a_function_doing_wa_returns_after_exactly_that_time_to_its_expression():
    c = controller()
    last = run(c, "OP(8, ON)\nVR(0) = pause_ms(100) + 1\nOP(9, ON)\n")
    assert "error" not in last and last["state"] == "stopped"
    # the call's statement starts at 100 µs, waits 100 ms, then costs its 100 µs
    assert outputs(c) == [(0, 8), (100_200, 9)]
    assert c.vr[0] == 201.0
    assert c.vr[50] == 1.0  # the statements before the wait ran once, not again on resuming


def test_a_process_waiting_in_a_function_is_as_if_the_wait_were_inline():
    inline, called = controller(), controller()
    run(inline, "OP(8, ON)\nWA(40)\nOP(9, ON)\n")
    run(called, "OP(8, ON)\npause_ms(40)\nOP(9, ON)\n")  # the call alone as a statement
    assert outputs(called) == outputs(inline) == [(0, 8), (40_200, 9)]


def test_nested_calls_wait_in_turn_and_the_calls_already_returned_are_not_run_again():
    c = controller()
    last = run(c, "VR(0) = twice(30) + pause_ms(10)\nOP(9, ON)\n")
    assert "error" not in last
    # twice: 30 + 30 ms, then pause_ms: 10 ms; the statement began at 0, costs 100 µs
    assert outputs(c) == [(70_100, 9)]
    assert c.vr[0] == (60 + 60 + 1) + 20
    assert c.vr[50] == 3.0  # three pause_ms calls, each counted once


def test_a_function_called_in_an_if_condition_waits_then_the_branch_is_taken():
    c = controller()
    run(c, "IF twice(20) = 81 THEN\n  OP(10, ON)\nELSE\n  OP(11, ON)\nENDIF\n"
           "IF pause_ms(5) > 100 THEN OP(12, ON) ELSE OP(13, ON)\n")
    # IF at 0 waits 40 ms, OP(10) at 40.1 ms; the one-line IF at 40.2 waits 5 ms -> 45.2
    assert outputs(c) == [(40_100, 10), (45_300, 13)]


def test_a_function_in_a_while_condition_waits_each_time_it_is_tested():
    c = controller()
    run(c, "n = 0\nWHILE pause_ms(10) > 0 AND n < 3\n  n = n + 1\nWEND\nOP(9, ON)\n")
    # four tests of 10 ms each: n = 0 at 0, WHILE at 0.1 ms, body / WEND 0.2 ms a round
    assert c.vr[50] == 4.0
    assert outputs(c) == [(40_000 + 100 * (2 + 3 * 3), 9)]


def test_wait_until_inside_a_function_waits_for_its_condition_reading_the_functions_names():
    c = controller()
    c.store_program("T", "VR(0) = settle(5) * 10\nOP(9, ON)\n")
    c.run_program("T", 1)
    run_to(c, 0.0205)
    assert c.vr[0] == 0.0 and outputs(c) == []
    c.vr[60] = 7.0  # tested once a servo period from here
    run_to(c, 0.1)
    (t9, out), = outputs(c)
    assert out == 9 and t9 == 21_100  # seen at the period at 21 ms, then 100 µs
    assert c.vr[0] == 70.0


def test_a_function_moving_into_a_full_buffer_waits_until_the_buffer_frees():
    inline, called = controller(), controller()
    head = "MOVE(100) AXIS(0)\nMOVE(100) AXIS(0)\n"
    run(inline, head + "MOVE(100) AXIS(0)\nOP(9, ON)\n")
    run(called, head + "go(100)\nOP(9, ON)\n")

    def states(c):
        return [(round(t * 1e6), f["state"], f["line"], f.get("blocked_on"))
                for t, f in fields(c, "process", process=1)]

    # the third move waits at line 3 from 1.1 ms until the buffer frees at the 2 ms period
    assert states(called) == [
        (0, "running", 1, None), (100, "blocked", 2, "MOVE(100) AXIS(0)"),
        (1000, "running", 2, None), (1100, "blocked", 3, "MOVE(d) AXIS(0)"),  # library line
        (2000, "running", 3, None), (2200, "stopped", 4, None)]
    assert [s[:3] for s in states(called)] == [s[:3] for s in states(inline)]
    assert outputs(called) == outputs(inline) == [(2100, 9)]


def test_a_function_waiting_while_the_process_is_stopped_ends_cleanly():
    c = controller()
    c.store_program("T", "VR(0) = pause_ms(500)\nOP(9, ON)\n")
    c.run_program("T", 1)
    run_to(c, 0.1)
    c.stop_process(1)
    run_to(c, 1.0)
    last = fields(c, "process", process=1)[-1]
    assert last[1]["state"] == "stopped" and "error" not in last[1]
    assert round(last[0] * 1e6) == 100_000 and last[1]["line"] == 1
    assert c.vr[0] == 0.0 and outputs(c) == []
    c.run_program("T", 1)  # runs again from the start, with no trace of the stopped call
    run_to(c, 2.0)
    assert c.vr[0] == 1000.0 and c.vr[50] == 2.0


def test_stop_inside_a_function_ends_the_program_there():
    c = make(model="mc4xx")
    c.store_program("LIB", "FUNCTION quit() AS INTEGER\n  VR(1) = 1\n  STOP\n  VR(2) = 1\n"
                           "  RETURN 1\nENDFUNC\n")
    last = run(c, "VR(0) = quit()\nVR(3) = 1\n")
    assert last["state"] == "stopped" and "error" not in last and last["line"] == 1
    assert c.vr[:4] == [0.0, 1.0, 0.0, 0.0]


def test_an_error_in_a_condition_a_function_waits_on_names_the_function():
    c = make(model="mc4xx")
    c.store_program("LIB", "FUNCTION bad() AS INTEGER\n  WAIT UNTIL VR(VR(70)) > 1\n"
                           "  RETURN 1\nENDFUNC\n")
    c.store_program("T", "VR(0) = bad()\n")
    c.run_program("T", 1)
    run_to(c, 0.01)
    c.vr[70] = 1e9
    run_to(c, 0.1)
    last = fields(c, "process", process=1)[-1][1]
    assert last["state"] == "stopped" and "FUNCTION BAD, LIB line 2" in last["error"]


def test_on_basicerror_handles_an_error_after_a_function_waited():
    c = make(model="mc4xx")
    c.store_program("LIB", "FUNCTION late(t AS INTEGER) AS FLOAT\n  WA(t)\n  RETURN 1 / 0\n"
                           "ENDFUNC\n")
    run(c, "ON BASICERROR GOTO handler\nVR(0) = late(20)\nSTOP\nhandler:\nOP(9, ON)\n")
    # the call's statement at 100 µs waits 20 ms; its error goes to the handler at once
    assert outputs(c) == [(20_100, 9)]


def test_only_the_statements_holding_calls_are_call_sites():
    """The compiler wraps exactly the operations whose expressions call a library function
    (functions.call_site): the op built right after the call was compiled."""
    c = controller()
    text = ("a = 1\nIF twice(1) > 0 THEN\n  b = 2\nELSEIF pause_ms(1) THEN\n  b = 3\nENDIF\n"
            "FOR i = 1 TO pause_ms(1)\nNEXT i\nWHILE pause_ms(1) < 0\nWEND\nc = 4\n")
    code = compile_program(parse_program(text, "mc4xx"), "T", lambda n: None,
                           functions=c.functions())
    wrapped = {code.lines[pc] for pc, op in enumerate(code.ops)
               if op.__qualname__ == call_site(lambda c: None).__qualname__}
    assert wrapped == {2, 4, 7, 9}


def test_a_function_waits_in_select_case_a_case_value_an_until_and_a_moves_argument():
    c = controller()
    last = run(c, "SELECT_CASE pause_ms(10)\n  CASE pause_ms(5)\n    OP(10, ON)\n"
                  "  CASE 20\n    OP(11, ON)\nEND_CASE\n"
                  "REPEAT\n  n = n + 1\nUNTIL pause_ms(1) > 0 AND n = 2\n"
                  "MOVE(pause_ms(3) / 60) AXIS(0)\nOP(12, ON)\n")
    assert "error" not in last
    # SELECT_CASE at 0 waits 10 ms; CASE (5 -> 10, no match) at 10.1 waits 5; CASE 20 matches
    # at 15.2; OP(11) 15.3; REPEAT body 15.4, UNTIL 15.5 + 1 ms, body 16.6, UNTIL 16.7 + 1 ms;
    # the MOVE at 17.8 waits 3 ms, is issued at 20.8; OP(12) at 20.9
    assert outputs(c) == [(15_300, 11), (20_900, 12)]
    assert c.vr[50] == 5.0
    assert [f["mtype"] for _, f in fields(c, "move_start", axis=0)] == [1]
