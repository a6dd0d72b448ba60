"""``/controllers/{id}/faults``: seeded fault injection, each kind exercising a real host's
retry path over the controllers' own TCP protocols against a served motionsim (127.0.0.1)."""

from __future__ import annotations

import httpx
import pytest
from motionsim.app.settings import Settings

from tests.api.fault_hosts import RetryingHost


@pytest.fixture
def motionsim_settings():
    return Settings(clock={"mode": "virtual"}, pmac_port="auto", trio_port="auto")


def _add(motionsim, controller: str, spec: dict) -> httpx.Response:
    return motionsim.http.post(f"/controllers/{controller}/faults", json=spec)


def _faults(motionsim, controller: str = "pmac") -> list[dict]:
    return motionsim.http.get(f"/controllers/{controller}/faults").json()["faults"]


def _fault_events(motionsim, controller: str = "pmac") -> list[dict]:
    return motionsim.all_events(controller, types=["fault"])


def _pmac(motionsim, **kw) -> RetryingHost:
    return RetryingHost(motionsim.ports["pmac"], "pmac", **kw)


def test_a_delayed_reply_makes_the_host_time_out_reconnect_and_retry(motionsim):
    r = _add(motionsim, "pmac", {"kind": "reply_delay", "match": "^I16$", "delay_ms": 1500})
    assert r.status_code == 201
    fault = r.json()
    assert fault["id"] == "f1" and fault["injected"] == 0
    host = _pmac(motionsim, timeout_s=0.4)
    try:
        reply = host.command("I16")
    finally:
        host.close()
    assert host.outcomes == ["timeout", "ok"]
    assert reply.rstrip(b"\r\x06").strip() != b""
    (event,) = _fault_events(motionsim)
    assert event["fault"] == "f1" and event["kind"] == "reply_delay"
    assert event["command"] == "I16"
    assert _faults(motionsim)[0]["injected"] == 1


def test_a_dropped_reply_is_retried_and_other_commands_are_untouched(motionsim):
    _add(motionsim, "pmac", {"kind": "reply_drop", "match": "^P7", "nth": 2})
    host = _pmac(motionsim, timeout_s=0.3)
    try:
        host.command("P7=1")           # first matching: answered
        host.command("I16")            # not matching
        host.command("P7=2")           # second matching: executed, answer dropped, retried
    finally:
        host.close()
    assert host.outcomes == ["ok", "ok", "timeout", "ok"]
    assert motionsim.http.get("/controllers/pmac/variables/P7").json()["value"] == 2
    assert [e["command"] for e in _fault_events(motionsim)] == ["P7=2"]


def test_a_connection_reset_mid_reply_sends_part_of_it_then_the_host_reconnects(motionsim):
    _add(motionsim, "pmac", {"kind": "connection_reset", "match": "^I1[67]$",
                             "after_bytes": 1})
    host = _pmac(motionsim, timeout_s=2.0)
    try:
        reply = host.command("I17")
    finally:
        host.close()
    assert host.outcomes[0] in ("reset", "closed") and host.outcomes[-1] == "ok"
    assert len(host.log[0].reply) <= 1
    assert reply.endswith(b"\x06")
    assert _fault_events(motionsim)[0]["kind"] == "connection_reset"


def test_a_forced_error_on_the_nth_command_is_not_executed_and_the_retry_is(motionsim):
    _add(motionsim, "pmac", {"kind": "error_reply", "match": "^P5=", "nth": 2,
                             "error": "ERR003"})
    host = _pmac(motionsim)
    try:
        host.command("P5=1")
        host.command("P5=2")
    finally:
        host.close()
    assert host.outcomes == ["ok", "error", "ok"]
    assert b"\x07ERR003\r" in host.log[1].reply
    events = motionsim.all_events("pmac", types=["fault", "mvar"])
    assert [(e["kind"], e["command"], e["error"]) for e in events] == [
        ("error_reply", "P5=2", "ERR003")]
    assert motionsim.http.get("/controllers/pmac/variables/P5").json()["value"] == 2


def test_the_rest_terminal_sees_a_forced_error_too(motionsim):
    _add(motionsim, "pmac", {"kind": "error_reply", "error": "ERR001", "match": "^&1R"})
    r = motionsim.http.post("/controllers/pmac/terminal", json={"command": "&1R"}).json()
    assert r["error"] == "ERR001" and r["reply"] == ""


def test_a_dropped_trio_reply_is_retried_over_the_command_line(motionsim):
    _add(motionsim, "trio", {"kind": "reply_drop", "match": r"VR\(3\)"})
    host = RetryingHost(motionsim.ports["telnet"], "trio", timeout_s=0.3)
    try:
        host.command("")
        host.command("VR(3)=7")
        reply = host.command("PRINT VR(3)")
    finally:
        host.close()
    assert host.outcomes == ["ok", "timeout", "ok", "ok"]
    assert b"7" in reply
    (event,) = _fault_events(motionsim, "trio")
    assert event["command"] == "VR(3)=7"


def test_a_host_waiting_for_breq_falls_back_to_reading_the_level_when_the_edge_is_lost(
        motionsim):
    """The host's retry path: wait for the BREQ rising edge (run-until) with a timeout, then
    read the rotary buffer's ``breq`` level and write anyway. Each write of 10 lines leaves
    at least I17 = 10 lines ahead (BREQ low), so every refill needs a rising edge."""
    http = motionsim.http
    http.put("/controllers/pmac/variables", json={"I16": 5, "I17": 10})
    motionsim.terminal("pmac", "&1 DEFINE ROT 600")
    lines = ["INC LINEAR TA1 TS0 TM5"] + ["X1"] * 59
    seq = 1

    def write(n: int) -> None:
        nonlocal seq
        r = http.post("/controllers/pmac/coord/1/rotary/lines",
                      json={"lines": lines[seq - 1:seq - 1 + n], "first_seq": seq})
        assert r.status_code == 200, r.text
        seq += n

    write(12)
    http.post("/controllers/pmac/coord/1/run")
    assert _add(motionsim, "pmac", {"kind": "breq_lost", "cs": 1}).status_code == 201
    fallbacks = 0
    while seq <= len(lines):
        waited = http.post("/controllers/pmac/clock/run-until",
                           json={"event": {"type": "breq", "level": True}, "timeout_s": 0.5})
        if waited.json()["matched"] is None:
            if not http.get("/controllers/pmac/coord/1").json()["rotary"]["breq"]:
                continue
            fallbacks += 1  # the edge never came, but BREQ reads high: write anyway
        write(min(10, len(lines) - seq + 1))
    assert fallbacks == 1
    (event,) = _fault_events(motionsim)
    assert event["kind"] == "breq_lost" and event["cs"] == 1
    assert len(motionsim.all_events("pmac", types=["line_loaded"])) == len(lines)


def test_a_stall_delays_the_terminal_reply_until_the_background_runs_again(motionsim):
    """A stalled card answers nothing: the REST terminal's PR comes back pending and the
    reply arrives as a ``terminal_reply`` once the stall is over (the host's retry waits)."""
    r = _add(motionsim, "pmac", {"kind": "stall", "duration_ms": 1500})
    assert r.status_code == 201
    t0 = motionsim.clock("pmac").t
    first = motionsim.http.post("/controllers/pmac/terminal", json={"command": "I16"}).json()
    assert first["pending"] is True
    got = motionsim.http.post("/controllers/pmac/clock/run-until", json={
        "event": {"type": "terminal_reply", "command": "I16"}, "timeout_s": 2}).json()
    assert got["matched"] is not None
    assert got["matched"]["t"] >= t0 + 1.5
    (event,) = _fault_events(motionsim)
    assert event["kind"] == "stall"
    assert event["end_s"] - event["start_s"] == pytest.approx(1.5)


@pytest.mark.parametrize("spec, field", [
    ({"kind": "reply_delay"}, "reply_delay.delay_ms"),
    ({"kind": "reply_delay", "delay_ms": -1}, "reply_delay.delay_ms"),
    ({"kind": "reply_drop", "nth": 0}, "reply_drop.nth"),
    ({"kind": "reply_drop", "probability": 1.5}, "reply_drop.probability"),
    ({"kind": "reply_drop", "match": "("}, "reply_drop.match"),
    ({"kind": "reply_drop", "bogus": 1}, "reply_drop.bogus"),
    ({"kind": "error_reply", "error": "ERR3"}, "error_reply.error"),
    ({"kind": "stall", "duration_ms": 0}, "stall.duration_ms"),
    ({"kind": "breq_lost", "cs": 17}, "breq_lost.cs"),
    ({"kind": "connection_reset", "after_bytes": -1}, "connection_reset.after_bytes"),
])
def test_an_impossible_fault_is_422_naming_the_field_and_nothing_changes(motionsim, spec, field):
    before = motionsim.http.get("/controllers/pmac/events").json()["next"]
    r = _add(motionsim, "pmac", spec)
    assert r.status_code == 422
    assert r.json()["code"] == "validation_error" and r.json()["field"] == field
    assert _faults(motionsim) == []
    assert motionsim.http.get("/controllers/pmac/events",
                              params={"since": before}).json()["events"] == []


@pytest.mark.parametrize("kind", [{"kind": "nope"}, {}])
def test_an_unknown_or_missing_kind_is_422(motionsim, kind):
    r = _add(motionsim, "pmac", kind)
    assert r.status_code == 422
    assert "kind" in r.json()["message"]


@pytest.mark.parametrize("spec", [{"kind": "error_reply", "error": "ERR003"},
                                  {"kind": "stall", "duration_ms": 5},
                                  {"kind": "breq_lost"}])
def test_card_faults_are_pmac_only(motionsim, spec):
    r = _add(motionsim, "trio", spec)
    assert r.status_code == 422 and r.json()["field"] == "kind"
    assert _faults(motionsim, "trio") == []


def test_faults_are_listed_removed_one_by_one_and_cleared(motionsim):
    _add(motionsim, "pmac", {"kind": "reply_drop"})
    _add(motionsim, "pmac", {"kind": "reply_delay", "delay_ms": 5, "count": None, "seed": 4})
    listed = _faults(motionsim)
    assert [(f["id"], f["kind"]) for f in listed] == [("f1", "reply_drop"), ("f2", "reply_delay")]
    assert listed[1]["count"] is None and listed[1]["seed"] == 4
    assert motionsim.http.delete("/controllers/pmac/faults/f1").status_code == 204
    assert [f["id"] for f in _faults(motionsim)] == ["f2"]
    missing = motionsim.http.delete("/controllers/pmac/faults/f9")
    assert missing.status_code == 404 and "f9" in missing.json()["message"]
    assert motionsim.http.delete("/controllers/pmac/faults").status_code == 204
    assert _faults(motionsim) == []
    host = _pmac(motionsim, timeout_s=1.0)
    try:
        host.command("I16")
    finally:
        host.close()
    assert host.outcomes == ["ok"]


def test_a_delayed_trio_reply_makes_the_host_time_out_and_ask_again(motionsim):
    _add(motionsim, "trio", {"kind": "reply_delay", "match": "^PRINT", "delay_ms": 1200})
    host = RetryingHost(motionsim.ports["telnet"], "trio", timeout_s=0.4)
    try:
        host.command("")
        reply = host.command("PRINT 6*7")
    finally:
        host.close()
    assert host.outcomes == ["ok", "timeout", "ok"]
    assert b"42" in reply
    (event,) = _fault_events(motionsim, "trio")
    assert event["kind"] == "reply_delay" and event["command"] == "PRINT 6*7"
