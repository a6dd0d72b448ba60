"""The host-paced clock over REST: mode switch, holders resource, run-until outcomes, errors."""

from __future__ import annotations

import asyncio

import pytest

pytestmark = pytest.mark.anyio

BASE = "/controllers/d/clock"


async def test_patch_to_host_paced_with_a_holder_shows_it_acting(api):
    r = await api.patch(BASE, json={"mode": "host-paced", "reaction_s": 0.01,
                                    "holders": ["host"]})
    assert r.status_code == 200, r.text
    body = r.json()
    assert (body["mode"], body["reaction_s"], body["held_by"]) == ("host-paced", 0.01, ["host"])
    assert body["holders"] == [{"name": "host", "state": "acting", "since_t": 0.0,
                                "event": None, "until_t": None}]
    assert "lag_s" not in body


async def test_run_until_holds_reaction_s_after_the_event_then_release_frees_time(api):
    """The dummy ticks every 10 ms: ``host`` waits for tick 3 (t = 0.03) and acts 5 ms later;
    ``main`` advancing 1 s is held there until ``host`` is released."""
    await api.patch(BASE, json={"mode": "host-paced", "reaction_s": 0.005, "holders": ["host"]})
    main = asyncio.ensure_future(api.post(f"{BASE}/advance", json={"seconds": 1.0}))
    r = await api.post(f"{BASE}/run-until", json={"event": {"type": "tick", "n": 3},
                                                  "timeout_s": 5.0, "holder": "host"})
    body = r.json()
    assert (body["outcome"], body["matched"]["n"]) == ("matched", 3)
    assert body["clock"]["t"] == pytest.approx(0.035)
    await asyncio.sleep(0.05)
    assert (await api.get(BASE)).json()["t"] == pytest.approx(0.035)  # held while host acts
    assert not main.done()
    released = (await api.delete(f"{BASE}/holders/host")).json()
    assert [h["name"] for h in released["holders"]] == ["main"]
    assert (await main).json()["t"] == pytest.approx(1.0)
    ticks = (await api.get("/controllers/d/events", params={"type": "tick"})).json()["events"]
    assert len(ticks) == 100


async def test_a_released_holders_pending_wait_returns_released(api):
    await api.patch(BASE, json={"mode": "host-paced", "holders": ["main"]})
    wait = asyncio.ensure_future(api.post(f"{BASE}/run-until", json={
        "event": {"type": "never"}, "timeout_s": 5.0, "holder": "host"}))
    await asyncio.sleep(0.02)
    await api.delete(f"{BASE}/holders/host")
    body = (await wait).json()
    assert (body["matched"], body["outcome"]) == (None, "released")


async def test_holders_on_a_virtual_clock_are_409_and_bad_values_422_changing_nothing(api):
    assert (await api.put(f"{BASE}/holders/host")).status_code == 409
    r = await api.patch(BASE, json={"reaction_s": 0.1})
    assert r.status_code == 422 and r.json()["field"] == "reaction_s"
    for bad in ({"mode": "host-paced", "reaction_s": -1}, {"mode": "host-paced", "reaction_s": 61},
                {"mode": "host-paced", "holders": ["no spaces"]}):
        r = await api.patch(BASE, json=bad)
        assert r.status_code == 422, bad
    assert (await api.get(BASE)).json() == {"mode": "virtual", "factor": 1.0, "paused": False,
                                            "t": 0.0}


async def test_create_a_controller_on_a_host_paced_clock(api):
    r = await api.post("/controllers", json={"id": "hp", "kind": "dummy", "clock": {
        "mode": "host-paced", "reaction_s": 0.002, "holders": ["streamer"]}})
    assert r.status_code == 201, r.text
    clock = r.json()["clock"]
    assert (clock["mode"], clock["reaction_s"], clock["held_by"]) == (
        "host-paced", 0.002, ["streamer"])
