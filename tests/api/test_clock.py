"""/controllers/{id}/clock: read, patch, advance, run-until."""

from __future__ import annotations

import pytest

pytestmark = pytest.mark.anyio


async def test_advance_runs_the_virtual_clock_and_its_events(api):
    r = await api.post("/controllers/d/clock/advance", json={"seconds": 0.035})
    assert r.status_code == 200
    assert r.json() == {"mode": "virtual", "factor": 1.0, "paused": False,
                        "t": pytest.approx(0.035)}
    ev = (await api.get("/controllers/d/events")).json()["events"]
    assert [(e["type"], e["n"], e["t"]) for e in ev] == [
        ("tick", 1, pytest.approx(0.01)), ("tick", 2, pytest.approx(0.02)),
        ("tick", 3, pytest.approx(0.03))]


async def test_advance_processes_events_due_exactly_at_the_target(api):
    await api.post("/controllers/d/clock/advance", json={"seconds": 0.02})
    ev = (await api.get("/controllers/d/events")).json()["events"]
    assert [e["n"] for e in ev] == [1, 2]


async def test_advance_zero_is_a_no_op(api):
    r = await api.post("/controllers/d/clock/advance", json={"seconds": 0})
    assert r.json()["t"] == 0.0
    assert (await api.get("/controllers/d/events")).json()["events"] == []


@pytest.mark.parametrize("seconds", [-1, -0.001, "1e999", "NaN", "abc", None])
async def test_advance_negative_or_non_finite_is_422_and_nothing_moves(api, seconds):
    body = '{"seconds": %s}' % (seconds if not isinstance(seconds, str) else
                                (seconds if seconds in ("1e999", "NaN") else f'"{seconds}"'))
    if seconds is None:
        body = "{}"
    r = await api.post("/controllers/d/clock/advance", content=body.encode(),
                       headers={"content-type": "application/json"})
    assert r.status_code == 422, r.text
    assert r.json()["code"] == "validation_error"
    assert r.json()["field"] == "seconds"
    assert (await api.get("/controllers/d/clock")).json()["t"] == 0.0


async def test_advance_on_a_realtime_clock_is_409_conflict(api):
    await api.post("/controllers", json={"id": "rt", "kind": "dummy",
                                         "clock": {"mode": "realtime"}})
    r = await api.post("/controllers/rt/clock/advance", json={"seconds": 1})
    assert r.status_code == 409
    assert r.json()["code"] == "conflict"


async def test_patch_factor_and_pause_a_realtime_clock(api):
    await api.post("/controllers", json={"id": "rt", "kind": "dummy",
                                         "clock": {"mode": "realtime"}})
    r = await api.patch("/controllers/rt/clock", json={"factor": 10, "paused": True})
    assert r.status_code == 200
    body = r.json()
    assert (body["mode"], body["factor"], body["paused"]) == ("realtime", 10.0, True)
    t_paused = body["t"]
    r2 = await api.get("/controllers/rt/clock")
    assert r2.json()["t"] == t_paused  # a paused clock does not move


async def test_patch_mode_switches_clock_keeping_t(api):
    await api.post("/controllers/d/clock/advance", json={"seconds": 0.5})
    r = await api.patch("/controllers/d/clock", json={"mode": "realtime", "paused": True})
    assert r.json()["mode"] == "realtime"
    assert r.json()["t"] == pytest.approx(0.5)
    r = await api.patch("/controllers/d/clock", json={"mode": "virtual", "paused": False})
    assert r.json() == {"mode": "virtual", "factor": 1.0, "paused": False,
                        "t": pytest.approx(0.5)}


async def test_paused_virtual_clock_refuses_to_advance(api):
    await api.patch("/controllers/d/clock", json={"paused": True})
    r = await api.post("/controllers/d/clock/advance", json={"seconds": 1})
    assert r.status_code == 409


@pytest.mark.parametrize("body, field", [({"factor": 0}, "factor"), ({"factor": -2}, "factor"),
                                         ({"paused": "maybe"}, "paused"),
                                         ({"mode": "fast"}, "mode"), ({"speed": 2}, "speed")])
async def test_patch_bad_field_is_422_and_nothing_changes(api, body, field):
    r = await api.patch("/controllers/d/clock", json=body)
    assert r.status_code == 422
    assert r.json()["field"] == field
    assert (await api.get("/controllers/d/clock")).json()["factor"] == 1.0


async def test_run_until_stops_at_the_matching_event(api):
    r = await api.post("/controllers/d/clock/run-until",
                       json={"event": {"type": "tick", "n": 7}, "timeout_s": 5})
    assert r.status_code == 200
    body = r.json()
    assert body["matched"]["type"] == "tick"
    assert body["matched"]["n"] == 7
    assert body["matched"]["controller"] == "d"
    assert body["matched"]["t"] == pytest.approx(0.07)
    assert body["clock"]["t"] == pytest.approx(0.07)


async def test_run_until_only_matches_new_events(api):
    await api.post("/controllers/d/clock/advance", json={"seconds": 0.03})
    r = await api.post("/controllers/d/clock/run-until",
                       json={"event": {"type": "tick"}, "timeout_s": 1})
    assert r.json()["matched"]["n"] == 4


async def test_run_until_times_out_at_timeout_s(api):
    r = await api.post("/controllers/d/clock/run-until",
                       json={"event": {"type": "never"}, "timeout_s": 0.25})
    assert r.json()["matched"] is None
    assert r.json()["clock"]["t"] == pytest.approx(0.25)


async def test_run_until_on_realtime_waits_for_the_event(api):
    await api.post("/controllers", json={"id": "rt", "kind": "dummy",
                                         "clock": {"mode": "realtime", "factor": 1},
                                         "config": {"tick_s": 0.1}})
    # a tick still to come, however long the request took to arrive (a loaded machine)
    t_now = (await api.get("/controllers/rt/clock")).json()["t"]
    n = int(t_now / 0.1) + 3
    r = await api.post("/controllers/rt/clock/run-until",
                       json={"event": {"type": "tick", "n": n}, "timeout_s": 5})
    body = r.json()
    assert body["matched"]["n"] == n
    assert body["matched"]["t"] == pytest.approx(n * 0.1)
    assert body["clock"]["t"] >= n * 0.1


async def test_run_until_on_realtime_gives_up_after_timeout(api):
    await api.post("/controllers", json={"id": "rt", "kind": "dummy",
                                         "clock": {"mode": "realtime", "factor": 10}})
    r = await api.post("/controllers/rt/clock/run-until",
                       json={"event": {"type": "never"}, "timeout_s": 0.5})
    assert r.json()["matched"] is None
    assert r.json()["clock"]["t"] >= 0.5 - 0.02


@pytest.mark.parametrize("body, field", [
    ({"event": {"type": "tick"}, "timeout_s": -1}, "timeout_s"),
    ({"event": {"type": "tick"}}, "timeout_s"),
    ({"event": {"n": 1}, "timeout_s": 1}, "event.type"),
])
async def test_run_until_bad_body_is_422(api, body, field):
    r = await api.post("/controllers/d/clock/run-until", json=body)
    assert r.status_code == 422
    assert r.json()["field"] == field
    assert (await api.get("/controllers/d/clock")).json()["t"] == 0.0
