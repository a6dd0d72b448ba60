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
    before = ms.get_variable("pmac", "I16")
    assert ms.set_variable("pmac", "I16", before + 2) == before + 2
    assert ms.get_variable("pmac", "I16") == before + 2
    assert ms.terminal("pmac", "I16") == TerminalReply(f"{before + 2:g}", None, False)
    assert ms.coord("pmac", 1)["program"]["state"] == "waiting"  # ran out of rotary lines
    ms.abort("pmac", 1)
    assert ms.coord("pmac", 1)["program"]["state"] == "aborted"
    ms.delete_rotary("pmac", 1)
    assert ms.coord("pmac", 1)["rotary"] is None


def _running_rotary(ms, cs: int = 1) -> None:
    """Five 20 ms moves in a fresh rotary buffer, running for 30 ms (inside the second move)."""
    ms.define_rotary("pmac", cs, 600)
    ms.load_lines("pmac", cs, ["INC LINEAR TA10 TS0 TM20"] + ["X1"] * 5, first_seq=1)
    ms.run("pmac", cs)
    ms.advance("pmac", 0.03)


def test_quit_through_the_client_stops_at_the_end_of_the_move_in_progress(motionsim):
    ms = motionsim
    _running_rotary(ms)
    ms.quit("pmac", 1)
    assert ms.coord("pmac", 1)["program"]["state"] == "running"  # the move in progress finishes
    ms.advance("pmac", 0.2)
    assert ms.coord("pmac", 1)["program"]["state"] == "stopped"
    ends = ms.all_events("pmac", types=["move_end"])
    assert 2 <= len(ends) < 5  # stopped before the buffer ran out
    (stop,) = [e for e in ms.all_events("pmac", types=["program"]) if e["state"] == "stopped"]
    assert stop["t"] >= ends[-1]["t"]


def test_abort_through_the_client_stops_at_once_no_move_starts_after_it(motionsim):
    ms = motionsim
    _running_rotary(ms)
    ms.abort("pmac", 1)
    t_abort = ms.clock("pmac").t
    assert ms.coord("pmac", 1)["program"]["state"] == "aborted"
    ms.advance("pmac", 0.2)
    assert all(e["t"] <= t_abort for e in ms.all_events("pmac", types=["move_start"]))
    (aborted,) = ms.all_events("pmac", types=["program"])[1:]
    assert (aborted["state"], aborted["t"]) == ("aborted", t_abort)
    # the move in progress decelerates to a stop (Ixx15) well before its programmed end
    last_start = ms.all_events("pmac", types=["move_start"])[-1]
    last_end = ms.all_events("pmac", types=["move_end"])[-1]
    assert last_end["n"] == last_start["n"]
    assert t_abort < last_end["t"] < last_start["t"] + 0.020


def test_trio_resources_through_the_client(motionsim):
    ms = motionsim
    ms.set_axis("trio", 0, speed=100, accel=1000, decel=1000)
    ms.move("trio", 0, "MOVE", [10])
    ms.advance("trio", 0.002)  # at least one servo period: the move is loaded into MTYPE
    axis = ms.axis("trio", 0)
    assert (axis["mtype"], axis["speed"], axis["endmove"]) == (1, 100, 10)
    ms.advance("trio", 0.5)  # 10 units at 100 units/s with 0.1 s ramps: well done by then
    assert (ms.axis("trio", 0)["mtype"], ms.axis("trio", 0)["dpos"]) == (0, pytest.approx(10))
    ms.set_variable("trio", "VR(5)", 2)
    assert ms.get_variable("trio", "VR(5)") == 2
    ms.store_program("trio", "DEMO", "VR(6)=3\n")
    p = ms.run_program("trio", "DEMO")
    assert [(q["process"], q["program"]) for q in ms.processes("trio")] == [(p, "DEMO")]
    ms.advance("trio", 0.1)
    assert ms.get_variable("trio", "VR(6)") == 3
    assert [(q["process"], q["state"]) for q in ms.processes("trio")] == [(p, "stopped")]
    assert ms.terminal_state("trio") == {"locked": False, "pending": []}


def test_client_raises_the_error_body(motionsim):
    with pytest.raises(MotionSimHTTPError) as exc:
        motionsim.load_lines("pmac", 1, ["X1"])  # no rotary buffer defined
    assert (exc.value.status, exc.value.code) == (404, "not_found")
    assert exc.value.body["code"] == exc.value.code
    assert "DEFINE ROT" in exc.value.body["message"]


def test_tsrm_i6_a_refused_command_reaches_the_client_with_its_meaning(motionsim):
    """An ``ERRnnn`` answer carries the SRM meaning and the detail (the body's extra fields
    used to make the client raise ``TypeError``); a not-simulated command says so."""
    bad = motionsim.terminal("pmac", "X10")
    assert (bad.error, bad.error_meaning) == ("ERR005",
                                              "command allowed only with a buffer open")
    unsimulated = motionsim.terminal("pmac", "CHECKSUM")
    assert (unsimulated.error, unsimulated.not_simulated) == ("ERR003", True)
    assert "CHECKSUM" in unsimulated.detail


def test_a_paced_host_started_with_start_releases_its_holder_when_its_code_ends(motionsim):
    """Issue 36 item 4: a host thread that ended without ``release()`` held time still until
    the advance's 30 s wall cap (409). ``PacedHost.start`` releases the holder when the
    host's code ends, raising or not: the advance runs to its end and the host's error
    reaches the test."""
    import pytest as _pytest

    motionsim.host_paced("pmac", "h")
    host = motionsim.host("pmac", "h")

    def broken(h):
        h.sleep(0.1)  # acts once, then fails without releasing
        raise RuntimeError("host bug")

    done = host.start(broken)
    clock = motionsim.advance("pmac", 2.0)  # a 409 after 30 s if the holder were left
    assert clock.t >= 2.0 - 1e-9  # the host's 0.1 s came before or within the advance
    assert "h" not in {x["name"] for x in clock.holders}
    with _pytest.raises(RuntimeError, match="host bug"):
        done.result(timeout=30)
    host.close()


def test_recordings_through_the_client_page_to_the_whole_recording(motionsim):
    """``recording`` pages through GET .../gather (PMAC) and .../scope (Trio) to every sample
    (docs/API.md "Recordings"): here more samples than one page of the resource holds."""
    ms = motionsim
    for command in ("WY:$1000,9", "I5001=$001000 I5050=1 I5049=1 I5000=0",
                    "DEFINE GATHER 60000", "GATHER"):
        assert ms.terminal("pmac", command).error is None
    ms.advance("pmac", 60.0)  # 60 000 samples (one long word each) fill the buffer: stopped
    rec = ms.recording("pmac")
    assert rec["running"] is False and rec["total"] == 60000
    assert len(rec["columns"]["cycle"]) == 60000 and set(rec["columns"]["I5001"]) == {9.0}
    assert rec["columns"]["cycle"] == list(range(rec["columns"]["cycle"][0],
                                                 rec["columns"]["cycle"][0] + 60000))
    assert ms.terminal("trio", "SCOPE(ON, 1, 0, 10, VR(1))").error is None
    assert ms.terminal("trio", "TRIGGER").error is None
    ms.advance("trio", 0.1)
    scope = ms.recording("trio", "scope")
    assert scope["kind"] == "scope" and scope["total"] == 10
