"""Issue 22, "what reads wrong today", bullets 4 and 5: an infinite or NaN motion argument is an
error everywhere (the REST surface answers 422 for it), and command-line lines run strictly in
the order received, also when one is typed from an in-process host's callback (TN20: the
terminal queues what is typed while it is busy)."""

from __future__ import annotations

import pytest

from tests.sim.trio.conftest import fields, make, run_to


@pytest.mark.parametrize("command", ["MOVE(1e999)", "MOVE(1e308*10) AXIS(1)",
                                     "MOVEABS(10, 1e999)", "SPEED = 1e308 * 10"])
def test_issue22_infinite_argument_at_the_command_line_is_an_error_and_moves_nothing(command):
    c = make()
    r = c.terminal(command)
    assert r.done and r.error is not None
    assert "out of range" in r.error
    run_to(c, 0.1)
    assert c.log.events("move_start", "process_buffer") == []
    assert c.axis(0)["speed"] == 1000.0 and c.axis(1)["dpos"] == 0.0


def test_issue22_infinite_argument_in_a_program_stops_it_and_buffers_nothing():
    c = make()
    c.store_program("P", "big = 1e308\nMOVE(big * 10)\nVR(0) = 1\n")
    c.run_program("P", 1)
    run_to(c, 0.1)
    (_t, f), = fields(c, "process", process=1, state="stopped")
    assert f["line"] == 2 and "MOVE is not a finite number (inf)" in f["error"]
    assert c.log.events("move_start") == [] and c.vr[0] == 0.0


def test_tn20_a_line_typed_from_a_host_callback_waits_for_the_running_line():
    """The host listens to the event log and types ``VR(1)=2`` when it sees output 8 switch on;
    the line that switched it (``OP(8,ON):VR(1)=1``) must finish first."""
    c = make()
    typed = []

    def host(event) -> None:
        if event.type == "output" and not typed:
            r = c.terminal("VR(1)=2:? VR(1)")
            typed.append((r, r.done))

    c.log.listen(host)
    first = c.terminal("OP(8,ON):VR(1)=1:? VR(1)")
    ((second, done_at_once),) = typed
    assert not done_at_once  # queued behind the running line
    assert first.reply == "1.0000" and second.reply == "2.0000"
    assert c.vr[1] == 2.0
    replies = [e.fields["command"] for e in c.log.events("terminal_reply")]
    assert replies == ["VR(1)=2:? VR(1)"]  # the host's line was answered pending


def test_tn20_a_line_typed_from_a_callback_while_queued_lines_drain_keeps_its_place():
    """Process 0's buffers full: the terminal locks; two lines queue behind the blocked move.
    When it is buffered the queue drains; a line the host types on seeing the last queued
    line's output runs after that line, not in the middle of it."""
    c = make()
    for _ in range(3):
        c.terminal("MOVE(10)")
    blocked = c.terminal("MOVE(10)")  # MTYPE, NTYPE, process buffer full: locked
    assert not blocked.done and c.terminal_state()["locked"]
    q1 = c.terminal("VR(1)=1")
    q2 = c.terminal("OP(9,ON):VR(1)=VR(1)*10")  # the last queued line: the queue is empty
    typed = []

    def host(event) -> None:
        if event.type == "output" and event.fields.get("output") == 9 and not typed:
            typed.append(c.terminal("VR(1)=VR(1)+5"))

    c.log.listen(host)
    run_to(c, 0.2)
    assert blocked.done and q1.done and q2.done and typed[0].done
    assert c.vr[1] == 15.0  # (1 * 10) + 5: strictly in the order received
