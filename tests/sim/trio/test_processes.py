"""Trio BASIC processes: statements cost time, wait on buffers, share axes, fail alone."""

from __future__ import annotations

import pytest
from motionsim.sim.errors import Conflict, NotFound, ParseError

from tests.sim.trio.conftest import cycle, fields, run_to


def prints(c, process=None):
    return [f["text"] for _, f in fields(c, "print") if process in (None, f["process"])]


def run(c, text, process=1, until=1.0, name="P"):
    c.store_program(name, text)
    c.run_program(name, process)
    run_to(c, until)


def test_each_statement_costs_the_configured_time(trio):
    run(trio, "VR(1)=1\nVR(2)=2\nVR(3)=3\n", until=0.01)
    stopped = fields(trio, "process", state="stopped")
    assert stopped[0][0] == pytest.approx(0.0003)


BLOCK_IF = "IF VR(1)=1 THEN\n  VR(2)=1\nELSE\n  VR(3)=1\nENDIF\n"
LINE_IF = "IF VR(1)=1 THEN VR(2)=1 ELSE VR(3)=1\n"


@pytest.mark.parametrize("form", [BLOCK_IF, LINE_IF], ids=["block", "one-line"])
@pytest.mark.parametrize("vr1", [1, 0])
def test_else_and_endif_cost_no_statement_time_on_either_branch(trio, vr1, form):
    """Each executed statement costs ``statement_s`` (100 µs); the jumps the block structure
    adds — THEN's end skipping to ENDIF, the false test landing after ELSE, ENDIF itself —
    cost nothing: assignment, IF test, one branch body, assignment = 4 statements = 0.4 ms
    on either branch."""
    text = f"VR(1)={vr1}\n{form}VR(4)=1\n"
    run(trio, text, until=0.01)
    ((t, f),) = fields(trio, "process", state="stopped")
    assert t == pytest.approx(0.0004, abs=1e-12)
    assert (trio.get_variable("VR(2)"), trio.get_variable("VR(3)")) == (vr1, 1 - vr1)
    assert trio.get_variable("VR(4)") == 1


def test_flow_control(trio):
    text = """
total = 0
FOR i = 1 TO 10 STEP 3
  total = total + i
NEXT i
PRINT total
IF total > 20 THEN
  PRINT "big"
ELSEIF total > 10 THEN
  PRINT "medium"
ELSE
  PRINT "small"
ENDIF
IF total = 22 THEN PRINT "yes" ELSE PRINT "no"
n = 0
WHILE n < 3
  n = n + 1
WEND
REPEAT
  n = n - 1
UNTIL n <= 0
GOSUB show
FOR k = 3 TO 1 STEP -1 : PRINT k; : NEXT k
PRINT ""
GOTO done
PRINT "skipped"
show:
  PRINT "n=";n
  RETURN
done:
PRINT 7 MOD 3, -2^2, 2+3*4-1
"""
    run(trio, text)
    assert prints(trio) == [
        "22.0000", "big", "yes", "n=0.0000", "3.00002.00001.0000", "1.0000\t4.0000\t13.0000"
    ]


def test_wait_idle_resumes_in_the_servo_period_the_axis_goes_idle(trio):
    run(trio, "MOVE(10) AXIS(2)\nMOVE(10) AXIS(2)\nWAIT IDLE AXIS(2)\nVR(9)=DPOS AXIS(2)\n")
    assert trio.get_variable("VR(9)") == 20.0
    idle = [cycle(trio, t) for t, _ in fields(trio, "axis", axis=2, mtype=0, ntype=0)]
    assert idle == [42]
    stopped = fields(trio, "process", state="stopped")
    assert stopped[0][0] == pytest.approx(0.042 + 0.0002)  # WAIT then the VR line


def test_wait_loaded_waits_for_ntype_to_empty(trio):
    run(trio, "MOVE(10)\nMOVE(10)\nWAIT LOADED\nVR(1)=MTYPE\nVR(2)=NTYPE\n")
    assert (trio.get_variable("VR(1)"), trio.get_variable("VR(2)")) == (1.0, 0.0)


def test_wait_until_and_wa(trio):
    trio.store_program("SETTER", "WA(5)\nVR(3)=1\n")
    trio.store_program("WAITER", "WAIT UNTIL VR(3)=1\nVR(4)=VR(4)+1\n")
    trio.run_program("WAITER", 2)
    trio.run_program("SETTER", 3)
    run_to(trio, 0.1)
    assert trio.get_variable("VR(4)") == 1.0
    stopped = {f["process"]: t for t, f in fields(trio, "process", state="stopped")}
    assert stopped[3] == pytest.approx(0.0052)
    assert stopped[2] == pytest.approx(0.006 + 0.0002)  # re-tested at the next servo period


def test_two_processes_sharing_an_axis_each_with_their_own_process_buffer(trio):
    trio.store_program("A", "FOR i=1 TO 3\n MOVE(10) AXIS(0)\nNEXT i\nVR(1)=1\n")
    trio.store_program("B", "FOR i=1 TO 3\n MOVE(10) AXIS(0)\nNEXT i\nVR(2)=1\n")
    trio.run_program("A", 1)
    trio.run_program("B", 2)
    run_to(trio, 0.5)
    assert trio.axis(0)["dpos"] == 60.0
    blocked = {f["process"] for _, f in fields(trio, "process", state="blocked")}
    assert blocked == {1, 2}
    # six moves one after another on axis 0: each starts the period after the last ended
    starts = [cycle(trio, t) for t, _ in fields(trio, "move_start", axis=0)]
    assert starts == [1, 22, 43, 64, 85, 106]
    assert (trio.get_variable("VR(1)"), trio.get_variable("VR(2)")) == (1.0, 1.0)


def test_blocked_even_for_a_single_servo_period_is_reported(trio):
    """Each move waits in the process buffer for the next servo interrupt (TRM p. 8-130), so
    a second move line within one servo period blocks until then; a move ending at period e
    frees the process buffer at e + 2."""
    trio.set_axis(0, speed=10_000, accel=1e9, decel=1e9)
    run(trio, "FOR i=1 TO 4\n MOVE(1) AXIS(0)\nNEXT i\n", until=0.1)
    period = trio.clock.period_s
    got = [(round(t / period, 3), f["state"], f["line"], f.get("blocked_on"))
           for t, f in fields(trio, "process", process=1)]
    blocked = (2, "MOVE(1) AXIS(0)")
    assert got == [
        (0.0, "running", 1, None),
        (0.3, "blocked", *blocked), (1.0, "running", 2, None),  # 2nd: until the interrupt
        (1.2, "blocked", *blocked), (2.0, "running", 2, None),  # 3rd: likewise
        (2.2, "blocked", *blocked), (4.0, "running", 2, None),  # 4th: first end (2) + 2
        (4.2, "stopped", 3, None),
    ]
    ends = [cycle(trio, t) for t, _ in fields(trio, "move_end", axis=0)]
    assert ends == [2, 4, 6, 8] and ends[0] + 2 == 4
    assert trio.axis(0)["dpos"] == 4.0


@pytest.mark.parametrize(
    ("text", "line", "message"),
    [
        ("VR(1)=1\nVR(2)=1/0\nVR(3)=1\n", 2, "Divide by zero"),
        ("x=5\nVR(x*1000)=1\n", 2, "VR index out of range: 5000"),
        ("MOVE(10) AXIS(12)\n", 1, "Axis number out of range: 12"),
        ("RETURN\n", 1, "RETURN without GOSUB"),
    ],
)
def test_runtime_error_stops_only_that_process(trio, text, line, message):
    trio.store_program("BAD", text)
    trio.store_program("GOOD", "FOR i=1 TO 100\n VR(10)=i\nNEXT i\n")
    trio.run_program("GOOD", 2)
    trio.run_program("BAD", 1)
    run_to(trio, 0.1)
    (t, ev), = fields(trio, "process", process=1, state="stopped")
    assert ev["line"] == line
    assert ev["error"] == f"%[Process 1:Line {line}] - {message}"
    assert trio.get_variable("VR(3)") == 0.0
    assert trio.get_variable("VR(10)") == 100.0
    assert [p["state"] for p in trio.processes()] == ["stopped", "stopped"]


def test_stop_withdraws_the_waiting_move(trio):
    run(trio, "FOR i=1 TO 10\n MOVE(10) AXIS(0)\nNEXT i\n", until=0.005)
    assert trio.processes()[0]["state"] == "blocked"
    trio.stop_process(1)
    assert trio.processes()[0]["state"] == "stopped"
    run_to(trio, 1.0)
    assert trio.axis(0)["dpos"] == 30.0  # MTYPE, NTYPE and the process buffer, no 4th move


def test_run_and_stop_from_basic(trio):
    trio.store_program("CHILD", "WHILE TRUE\n VR(1)=VR(1)+1\n WA(1)\nWEND\n")
    run(trio, 'RUN "CHILD", 4\nWA(10)\nSTOP "CHILD"\nVR(2)=PROCNUMBER\n', until=0.1)
    states = {p["process"]: p["state"] for p in trio.processes()}
    assert states == {1: "stopped", 4: "stopped"}
    assert 8 <= trio.get_variable("VR(1)") <= 11
    assert trio.get_variable("VR(2)") == 1.0


def test_run_picks_the_highest_free_process_and_refuses_a_busy_one(trio):
    trio.store_program("LOOP", "WHILE TRUE\n WA(1)\nWEND\n")
    assert trio.run_program("LOOP") == 7
    assert trio.run_program("LOOP") == 6
    with pytest.raises(Conflict):
        trio.run_program("LOOP", 7)
    with pytest.raises(NotFound):
        trio.run_program("NOPE")
    with pytest.raises(Conflict):
        trio.delete_program("LOOP")


def test_parse_error_leaves_the_stored_program_unchanged(trio):
    trio.store_program("P", "VR(1)=1\n")
    with pytest.raises(ParseError) as err:
        trio.store_program("P", "VR(1)=1\nMOVE(10 AXIS(0)\n")
    assert (err.value.line, err.value.column) == (2, 9)
    assert trio.program("P") == "VR(1)=1\n"


def test_print_from_a_program_is_an_event(trio):
    run(trio, 'PRINT "at ";MTYPE AXIS(0)\n')
    assert fields(trio, "print") == [(0.0, {"process": 1, "channel": 0, "text": "at 0.0000"})]


def test_reset_clears_programs_and_buffers(trio):
    trio.store_program("LOOP", "WHILE TRUE\n MOVE(10)\nWEND\n")
    trio.run_program("LOOP", 1)
    run_to(trio, 0.01)
    trio.reset()
    assert trio.program_names() == [] and trio.processes() == []
    assert trio.axis(0)["mtype"] == 0
    seq = trio.log.last_seq
    run_to(trio, 0.5)
    assert all(e.type != "move_start" for e in trio.log.read(seq).events)


def test_a_program_of_only_a_remark_runs_and_stops_at_line_0():
    """A program with no statement (one remark line): its process runs and stops at once,
    reporting line 0 (no statement line) in both process events and the process resource."""
    from tests.sim.trio.conftest import fields, make, run_to

    c = make()
    c.store_program("E", "' just a remark\n")
    c.run_program("E", 3)
    run_to(c, 0.1)
    assert [f for _t, f in fields(c, "process") if f["process"] == 3] == [
        {"process": 3, "state": "running", "line": 0},
        {"process": 3, "state": "stopped", "line": 0}]
    assert c.processes() == [
        {"process": 3, "program": "E", "state": "stopped", "line": 0, "pmove": 0}]
