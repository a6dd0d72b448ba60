"""A program waiting at a move line whose process buffer was full (TN20-16; TRM MC206 p. 8-130,
PMOVE: the move waits in the process buffer until the next servo interrupt transfers it): it
goes on in the servo period its move is written to the buffer, reports ``running`` there, and
its next line starts one statement time later. A stop at that instant, before the program
has gone on, leaves it stopped. Virtual time only (``sim/trio/run/process.py``)."""

from __future__ import annotations

from motionsim.sim.simpy_adapter import triggered_at

from tests.sim.trio.conftest import fields, make, run_to

PROGRAM = "MOVE(10) AXIS(0)\nMOVE(10) AXIS(1)\nVR(0)=1\n"
PERIOD = 0.001
STATEMENT = 100e-6  # statement_us default


def _run(c) -> None:
    c.store_program("P", PROGRAM)
    c.run_program("P", 1)


def test_the_blocked_line_goes_on_in_the_period_its_move_is_placed():
    """Line 2 blocks at 100 µs (the buffer holds line 1's move); the interrupt at 1 ms moves
    line 1's move on and writes line 2's into the buffer; ``running`` follows that write at
    1 ms, and line 3 runs one statement time later."""
    c = make()
    _run(c)
    run_to(c, PERIOD + STATEMENT / 2)
    states = [(t, f["state"], f["line"]) for t, f in fields(c, "process", process=1)]
    assert states == [(0.0, "running", 1), (STATEMENT, "blocked", 2), (PERIOD, "running", 2)]
    events = [(e.type, e.fields.get("state"), e.fields.get("mtype"))
              for e in c.log.events() if e.t == PERIOD]
    put = events.index(("process_buffer", None, 1))
    assert events[put + 1:] == [("process", "running", None)]
    assert c.get_variable("VR(0)") == 0.0
    run_to(c, PERIOD + STATEMENT * 1.5)
    assert c.get_variable("VR(0)") == 1.0


def test_a_stop_at_the_instant_of_placement_leaves_the_program_stopped():
    """STOP in the servo period that places the blocked move, after the interrupt and before the
    program goes on: the move stays placed (it runs), the program reports ``stopped`` and
    never ``running`` again, and line 3 never runs."""
    c = make()
    _run(c)
    # queued (URGENT, at 1 ms) from 0.5 ms, after the interrupt of 1 ms was: it runs right
    # after that interrupt, before the program's own turn at 1 ms
    triggered_at(c.env, PERIOD / 2, lambda _ev: triggered_at(
        c.env, PERIOD, lambda _e: c.stop_process(1)))
    run_to(c, 0.1)
    states = [(t, f["state"]) for t, f in fields(c, "process", process=1)]
    assert states == [(0.0, "running"), (STATEMENT, "blocked"), (PERIOD, "stopped")]
    assert c.get_variable("VR(0)") == 0.0
    assert [f["mtype"] for _, f in fields(c, "move_start", axis=1)] == [1]
    assert c.processes()[0]["state"] == "stopped"
