"""The typed client against the real PMAC and Trio kinds, through the ``motionsim`` fixture."""

from __future__ import annotations

import pytest
from motionsim.app.client import LinesAccepted, MotionSimHTTPError, TerminalReply


def test_pmac_rotary_stream_through_the_client(motionsim):
    ms = motionsim
    assert [c["id"] for c in ms.controllers()] == ["pmac", "trio"]
    ms.define_rotary("pmac", 1, 600)
    acc = ms.load_lines("pmac", 1, ["INC LINEAR TA10 TS0 TM20", "X1", "X1"], first_seq=1)
    assert isinstance(acc, LinesAccepted)
    assert (acc.accepted, acc.lines_ahead, acc.extra["stored"]) == (3, 3, 3)
    again = ms.load_lines("pmac", 1, ["INC LINEAR TA10 TS0 TM20", "X1", "X1"], first_seq=1)
    assert (again.accepted, again.extra["stored"]) == (3, 0)
    ms.run("pmac", 1)
    res = ms.run_until("pmac", "move_end", 1.0, cs=1, n=3)
    assert res.matched is not None and res.clock.t == pytest.approx(res.matched["t"])
    assert ms.coord("pmac", 1)["rotary"]["size_words"] == 600
    assert ms.terminal("pmac", "PR") == TerminalReply("0", None, False)
    assert ms.get_variable("pmac", "I16") == ms.set_variable("pmac", "I16", ms.get_variable(
        "pmac", "I16"))
    ms.quit("pmac", 1)
    ms.abort("pmac", 1)
    ms.delete_rotary("pmac", 1)
    assert ms.coord("pmac", 1)["rotary"] is None


def test_trio_resources_through_the_client(motionsim):
    ms = motionsim
    ms.set_axis("trio", 0, speed=100, accel=1000, decel=1000)
    placed = ms.move("trio", 0, "MOVE", [10])
    assert placed["placed"] in ("mtype", "ntype", "process_buffer")
    assert ms.axis("trio", 0)["speed"] == 100
    ms.set_variable("trio", "VR(5)", 2)
    assert ms.get_variable("trio", "VR(5)") == 2
    ms.store_program("trio", "DEMO", "VR(6)=3\n")
    p = ms.run_program("trio", "DEMO")
    ms.advance("trio", 0.1)
    assert ms.get_variable("trio", "VR(6)") == 3
    assert isinstance(p, int) and isinstance(ms.processes("trio"), list)
    assert ms.terminal_state("trio") == {"locked": False, "pending": []}


def test_client_raises_the_error_body(motionsim):
    with pytest.raises(MotionSimHTTPError) as exc:
        motionsim.load_lines("pmac", 1, ["X1"])  # no rotary buffer defined
    assert exc.value.status in (404, 409)
    assert exc.value.body["code"] == exc.value.code
