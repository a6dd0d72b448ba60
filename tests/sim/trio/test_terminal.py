"""The command line (process 0): Trio number format, and the terminal that locks on a move."""

from __future__ import annotations

from tests.sim.trio.conftest import fields, next_period, run_to


def test_print_answers_in_trio_number_format(trio):
    assert trio.terminal("VR(5)=2").reply == ""
    assert trio.terminal("? VR(5)").reply == "2.0000"
    assert trio.terminal("PRINT VR(5)*1.5, -VR(5)").reply == "3.0000\t-2.0000"
    assert trio.terminal('PRINT "pos ";DPOS AXIS(1)').reply == "pos 0.0000"
    assert trio.terminal("? 2+3*4^2").reply == "50.0000"
    assert trio.terminal("? 1=1, 1<>1, NOT 0").reply == "-1.0000\t0.0000\t-1.0000"


def test_command_line_never_moves_the_clock(trio):
    trio.terminal("MOVE(10) AXIS(0)")
    trio.terminal("? MTYPE AXIS(0)")
    assert trio.now == 0.0


def test_axis_parameters_read_and_written_with_axis_modifier(trio):
    trio.terminal("SPEED AXIS(1)=250")
    assert trio.axis(1)["speed"] == 250.0
    assert trio.terminal("? SPEED AXIS(1)").reply == "250.0000"
    trio.terminal("BASE(1)")
    assert trio.terminal("? SPEED").reply == "250.0000"


def test_terminal_locks_on_a_move_that_cannot_be_buffered(trio):
    for _ in range(3):
        assert trio.terminal("MOVE(10) AXIS(0)").done
        next_period(trio)
    blocked = trio.terminal("MOVE(10) AXIS(0)")
    assert not blocked.done
    later = trio.terminal("? VR(1)")
    assert not later.done
    assert trio.terminal_state() == {"locked": True, "pending": ["MOVE(10) AXIS(0)", "? VR(1)"]}
    assert fields(trio, "terminal") == [(0.0035, {"locked": True})]
    assert fields(trio, "process", process=0) == [
        (0.0035, {"process": 0, "state": "blocked", "line": 0, "blocked_on": "MOVE(10) AXIS(0)"})
    ]
    run_to(trio, 0.1)
    # unlocked in the servo period where process 0's buffer drains (2 after the first end)
    assert [(round(t * 1e3, 1), f["locked"]) for t, f in fields(trio, "terminal")] == [
        (3.5, True), (23.0, False)
    ]
    assert blocked.done and blocked.error is None and blocked.t_done == 0.023
    assert later.done and later.reply == "0.0000"
    replies = [f for _, f in fields(trio, "terminal_reply")]
    assert replies == [
        {"command": "MOVE(10) AXIS(0)", "reply": "", "error": None},
        {"command": "? VR(1)", "reply": "0.0000", "error": None},
    ]
    assert trio.terminal_state() == {"locked": False, "pending": []}


def test_queued_move_can_lock_the_terminal_again(trio):
    for _ in range(3):
        trio.terminal("MOVE(10) AXIS(0)")
        next_period(trio)
    trio.terminal("MOVE(10) AXIS(0)")
    again = trio.terminal("MOVE(10) AXIS(0)")
    run_to(trio, 0.03)
    assert not again.done
    locks = [(round(t * 1e3, 1), f["locked"]) for t, f in fields(trio, "terminal")]
    assert locks == [(3.5, True), (23.0, False), (23.0, True)]
    run_to(trio, 0.1)
    assert again.done
    assert [(round(t * 1e3, 1), f["locked"]) for t, f in fields(trio, "terminal")][-1] == (
        44.0, False
    )


def test_rest_of_the_line_runs_after_the_move_is_buffered(trio):
    for _ in range(3):
        trio.terminal("MOVE(10) AXIS(0)")
        next_period(trio)
    r = trio.terminal("MOVE(10) AXIS(0) : ? NTYPE AXIS(0)")
    run_to(trio, 0.1)
    assert r.reply == "1.0000"


def test_errors_are_answered_not_raised(trio):
    r = trio.terminal("? 1/0")
    assert r.done and r.error == "%[Process 0:Line 0] - Divide by zero"
    assert trio.terminal("? VR(99999)").error.endswith("VR index out of range: 99999")
    assert trio.terminal("MOVE(1) AXIS(9)").error.endswith("Axis number out of range: 9")
    assert "column 7" in trio.terminal("? (1+2").error
    no_locals = "Local variables cannot be used at the command line: X"
    assert trio.terminal("x=1").error.endswith(no_locals)
    assert trio.terminal("WA(10)").error.endswith("Command not allowed at the command line")
    assert trio.terminal("FOO").error.endswith("unknown command 'FOO' at column 1")
    assert trio.axis(0)["mtype"] == 0


def test_command_line_has_no_locals_but_several_statements_per_line(trio):
    r = trio.terminal("FOR i=1 TO 3 : VR(i)=i*2 : NEXT i")
    assert r.error.endswith("Local variables cannot be used at the command line: I")
    assert trio.terminal("TABLE(10, 1, 2, 3) : ? TABLE(12)").reply == "3.0000"


def test_print_formats_decimals_and_width(trio):
    trio.terminal("VR(1)=3.14159")
    assert trio.terminal("? VR(1)[2]").reply == "3.14"
    assert trio.terminal("PRINT VR(1)[0]; VR(1)[8,3]").reply == "3   3.142"
    assert "column 13" in trio.terminal("PRINT VR(1)[a]").error


def test_moves_buffered_counts_mtype_and_ntype(trio):
    for _ in range(3):
        trio.terminal("MOVE(10) AXIS(0)")
        next_period(trio)
    assert trio.terminal("? MOVES_BUFFERED AXIS(0)").reply == "2.0000"
    assert trio.axis(0)["moves_buffered"] == 2
