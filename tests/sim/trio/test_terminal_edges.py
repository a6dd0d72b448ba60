"""The Trio command line (process 0): every PRINT of a line answers its own output line
(Trio BASIC PRINT ends its output with CR LF), a not-simulated command is answered naming it
and its column, and the process event after an unlock names process 0, line 0 (API.md
``process`` event)."""

from __future__ import annotations

from tests.sim.trio.conftest import fields, next_period, run_to


def test_each_print_of_a_command_line_is_its_own_output_line(trio):
    assert trio.terminal("PRINT 1: PRINT 2").reply == "1.0000\r\n2.0000"
    assert trio.terminal("PRINT 1: PRINT 2: PRINT 3").reply == "1.0000\r\n2.0000\r\n3.0000"


def test_a_not_simulated_command_is_answered_naming_it_and_its_column(trio):
    for line, column in (("TRON", 1), ("VR(1)=1: TRON", 10)):
        reply = trio.terminal(line)
        message = f"TRON is a Trio BASIC command that is not simulated at column {column}"
        assert reply.detail == ("not_simulated", message)
        assert reply.error == f"%[Process 0:Line 0] - {message}"


def test_the_command_line_runs_again_as_process_0_line_0_when_its_move_is_buffered(trio):
    for _ in range(3):
        trio.terminal("MOVE(10) AXIS(0)")
        next_period(trio)
    trio.terminal("VR(1)=2: MOVE(10) AXIS(0)")
    run_to(trio, 0.1)
    assert fields(trio, "process", process=0) == [
        (0.0035, {"process": 0, "state": "blocked", "line": 0,
                  "blocked_on": "VR(1)=2: MOVE(10) AXIS(0)"}),
        (0.023, {"process": 0, "state": "running", "line": 0})]


def test_a_command_line_of_300_statements_runs_them_all(trio):
    """A long command line (300 ``VR(n)=n`` statements, more ops than CPython caches small
    ints for) runs to its end and answers nothing."""
    reply = trio.terminal(": ".join(f"VR({n})={n}" for n in range(300)))
    assert (reply.error, reply.reply) == (None, "")
    assert trio.terminal("PRINT VR(299), VR(150)").reply == "299.0000\t150.0000"
