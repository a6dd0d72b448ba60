"""Trio REST resources: axes, moves (409 / ?wait=true), programs, processes, VR, terminal."""

from __future__ import annotations

import pytest
from motionsim.api.main import create_app

from tests.api.conftest import FAST, clock_t
from tests.conftest import dummy_settings, rest_client

pytestmark = pytest.mark.anyio

BASE = "/controllers/t"


async def test_axis_resource_and_patch(trio_api):
    r = await trio_api.get(f"{BASE}/axes/0")
    assert r.status_code == 200
    body = r.json()
    assert {k: body[k] for k in ("axis", "mtype", "ntype", "dpos", "speed")} == {
        "axis": 0, "mtype": 0, "ntype": 0, "dpos": 0.0, "speed": 1000.0
    }
    r = await trio_api.patch(f"{BASE}/axes/1", json={"speed": 250, "units": 4})
    assert r.status_code == 200 and r.json()["speed"] == 250.0 and r.json()["units"] == 4.0
    r = await trio_api.patch(f"{BASE}/axes/1", json={"speed": -1})
    assert r.status_code == 422 and r.json()["code"] == "validation_error"
    assert (await trio_api.get(f"{BASE}/axes/99")).status_code == 404


async def _one_period(api) -> None:
    await api.post(f"{BASE}/clock/advance", json={"seconds": 0.001})


async def test_moves_placed_then_409_with_nothing_queued(trio_api):
    """Each move enters process 0's process buffer; the servo interrupt moves it on to
    MTYPE / NTYPE (M206-320), so moves one servo period apart fill MTYPE, NTYPE, then the
    process buffer."""
    placed = []
    for _ in range(3):
        r = await trio_api.post(f"{BASE}/axes/0/moves", json={"type": "MOVE", "args": [10]})
        assert r.status_code == 201
        placed.append(r.json()["placed"])
        await _one_period(trio_api)
    assert placed == ["process_buffer"] * 3
    axis = (await trio_api.get(f"{BASE}/axes/0")).json()
    assert (axis["mtype"], axis["ntype"]) == (1, 1)
    before = (await trio_api.get(f"{BASE}/events")).json()["next"]
    r = await trio_api.post(f"{BASE}/axes/0/moves", json={"type": "MOVE", "args": [10]})
    assert r.status_code == 409 and r.json()["code"] == "buffer_full"
    assert (await trio_api.get(f"{BASE}/events", params={"since": before})).json()["events"] == []
    assert await clock_t(trio_api, BASE) == pytest.approx(0.003)


async def test_second_move_in_one_servo_period_is_409_until_the_interrupt(trio_api):
    r = await trio_api.post(f"{BASE}/axes/0/moves", json={"type": "MOVE", "args": [10]})
    assert r.status_code == 201
    r = await trio_api.post(f"{BASE}/axes/1/moves", json={"type": "MOVE", "args": [10]})
    assert r.status_code == 409 and r.json()["code"] == "buffer_full"
    r = await trio_api.post(f"{BASE}/terminal", json={"command": "? PMOVE PROC(0)"})
    assert r.json() == {"reply": "1.0000", "error": None, "pending": False}
    await _one_period(trio_api)
    r = await trio_api.post(f"{BASE}/terminal", json={"command": "? PMOVE PROC(0)"})
    assert r.json()["reply"] == "0.0000"
    r = await trio_api.post(f"{BASE}/axes/1/moves", json={"type": "MOVE", "args": [10]})
    assert r.status_code == 201


async def test_wait_true_advances_a_virtual_clock_until_buffered(trio_api):
    for _ in range(3):
        await trio_api.post(f"{BASE}/axes/0/moves", json={"type": "MOVE", "args": [10]})
        await _one_period(trio_api)
    r = await trio_api.post(f"{BASE}/axes/0/moves", params={"wait": "true"},
                            json={"type": "MOVE", "args": [10]})
    assert r.status_code == 201 and r.json() == {"placed": "process_buffer"}
    assert await clock_t(trio_api, BASE) == pytest.approx(0.023)


async def test_wait_true_times_out_with_nothing_queued(trio_api):
    for body in ({"type": "FORWARD"}, {"type": "MOVE", "args": [1]}):
        await trio_api.post(f"{BASE}/axes/0/moves", json=body)
        await _one_period(trio_api)
    await trio_api.post(f"{BASE}/axes/0/moves", json={"type": "MOVE", "args": [1]})
    r = await trio_api.post(f"{BASE}/axes/0/moves", params={"wait": "true", "timeout_s": 0.5},
                            json={"type": "MOVE", "args": [1]})
    assert r.status_code == 409 and r.json()["code"] == "buffer_full"
    t_cancel = await clock_t(trio_api, BASE)
    r = await trio_api.post(f"{BASE}/terminal", json={"command": "CANCEL AXIS(0)"})
    await trio_api.post(f"{BASE}/clock/advance", json={"seconds": 1})
    # the two 1-unit moves ran after the cancelled FORWARD, the withdrawn one did not
    events = (await trio_api.get(f"{BASE}/events", params={"type": "move_start"})).json()["events"]
    assert [e["mtype"] for e in events] == [10, 1, 1]
    # FORWARD ran at SPEED 1000 from its start to the CANCEL, with equal ACCEL and DECEL ramps
    # (the distance the ramp-up loses the ramp-down gains): SPEED * t_run; then the two 1-unit
    # moves added 2
    t_run = t_cancel - events[0]["t"]
    axis = (await trio_api.get(f"{BASE}/axes/0")).json()
    assert (axis["mtype"], axis["ntype"]) == (0, 0)
    assert axis["dpos"] == pytest.approx(1000 * t_run + 2, abs=1e-6)


async def test_bad_move_bodies(trio_api):
    r = await trio_api.post(f"{BASE}/axes/0/moves", json={"type": "JUMP", "args": [1]})
    assert r.status_code == 422
    r = await trio_api.post(f"{BASE}/axes/0/moves", json={"type": "MOVECIRC", "args": [1]})
    assert r.status_code == 422 and r.json()["field"] == "args"


async def test_program_put_get_run_processes(trio_api):
    text = "FOR i=1 TO 4\n  MOVE(10) AXIS(0)\nNEXT i\nWAIT IDLE AXIS(0)\nVR(7)=DPOS AXIS(0)\n"
    r = await trio_api.put(f"{BASE}/programs/demo", content=text,
                           headers={"content-type": "text/plain"})
    assert r.status_code == 201 and r.json() == {"name": "DEMO", "lines": 5}
    r = await trio_api.get(f"{BASE}/programs/DEMO")
    assert r.status_code == 200 and r.text == text
    assert (await trio_api.get(f"{BASE}/programs")).json() == {"programs": ["DEMO"]}
    r = await trio_api.post(f"{BASE}/programs/demo/run", json={"process": 2})
    assert r.json() == {"process": 2}
    await trio_api.post(f"{BASE}/clock/advance", json={"seconds": 0.01})
    procs = (await trio_api.get(f"{BASE}/processes")).json()
    assert procs == [{"process": 2, "program": "DEMO", "state": "blocked", "line": 2,
                      "blocked_on": "MOVE(10) AXIS(0)", "pmove": 1, "error": None}]
    await trio_api.post(f"{BASE}/clock/advance", json={"seconds": 1})
    assert (await trio_api.get(f"{BASE}/variables/VR(7)")).json() == {"name": "VR(7)",
                                                                       "value": 40.0}
    assert (await trio_api.get(f"{BASE}/processes")).json()[0]["state"] == "stopped"


async def test_program_parse_error_is_422_with_line_and_column_and_keeps_the_old_text(trio_api):
    await trio_api.put(f"{BASE}/programs/p", content="VR(1)=1\n")
    r = await trio_api.put(f"{BASE}/programs/p", content="VR(1)=1\nIF VR(1)=1 THEN\n")
    assert r.status_code == 422
    body = r.json()
    assert (body["code"], body["line"], body["column"]) == ("parse_error", 2, 1)
    assert (await trio_api.get(f"{BASE}/programs/p")).text == "VR(1)=1\n"


async def test_program_not_found_delete_and_stop(trio_api):
    assert (await trio_api.get(f"{BASE}/programs/none")).status_code == 404
    assert (await trio_api.post(f"{BASE}/programs/none/run")).status_code == 404
    await trio_api.put(f"{BASE}/programs/loop", content="WHILE TRUE\n WA(1)\nWEND\n")
    assert (await trio_api.post(f"{BASE}/programs/loop/run")).json() == {"process": 7}
    assert (await trio_api.delete(f"{BASE}/programs/loop")).status_code == 409
    r = await trio_api.post(f"{BASE}/processes/7/stop")
    assert r.status_code == 200 and r.json()["state"] == "stopped"
    assert (await trio_api.delete(f"{BASE}/programs/loop")).status_code == 204
    assert (await trio_api.post(f"{BASE}/processes/3/stop")).status_code == 404


async def test_terminal_locks_and_reports_pending(trio_api):
    for _ in range(3):
        r = await trio_api.post(f"{BASE}/terminal", json={"command": "MOVE(10) AXIS(0)"})
        assert r.json() == {"reply": "", "error": None, "pending": False}
        await _one_period(trio_api)
    r = await trio_api.post(f"{BASE}/terminal", json={"command": "MOVE(10) AXIS(0)"})
    assert r.json() == {"reply": "", "error": None, "pending": True}
    r = await trio_api.post(f"{BASE}/terminal", json={"command": "? MTYPE AXIS(0)"})
    assert r.json()["pending"] is True
    assert await clock_t(trio_api, BASE) == pytest.approx(0.003)
    r = await trio_api.get(f"{BASE}/terminal")
    assert r.json() == {"locked": True, "pending": ["MOVE(10) AXIS(0)", "? MTYPE AXIS(0)"]}
    r = await trio_api.post(f"{BASE}/clock/run-until",
                            json={"event": {"type": "terminal", "locked": False}, "timeout_s": 1})
    assert r.json()["matched"]["t"] == pytest.approx(0.023)
    ev = (await trio_api.get(f"{BASE}/events", params={"type": "terminal_reply"})).json()
    assert [(e["command"], e["reply"]) for e in ev["events"]] == [
        ("MOVE(10) AXIS(0)", ""), ("? MTYPE AXIS(0)", "1.0000")
    ]


async def test_trio_routes_on_a_pmac_like_kind_are_404():
    async with rest_client(create_app(dummy_settings())) as client:
        r = await client.get("/controllers/d/axes/0")
        assert r.status_code == 404 and r.json()["code"] == "not_found"


async def test_wait_true_on_a_realtime_clock_awaits_the_placement():
    settings = dummy_settings(controllers=[{
        "id": "t", "kind": "trio", "clock": {"mode": "realtime", "factor": 20.0}, "config": FAST,
    }])
    async with rest_client(create_app(settings)) as api:
        for _ in range(3):
            r = await api.post(f"{BASE}/axes/0/moves", json={"type": "MOVE", "args": [1000]})
            assert r.status_code == 201
        r = await api.post(f"{BASE}/axes/0/moves", params={"wait": "true"},
                           json={"type": "MOVE", "args": [1000]})
        assert r.status_code == 201 and r.json() == {"placed": "process_buffer"}
        assert await clock_t(api, BASE) >= 1.0  # the first 1000-unit move ended (1.01 s)
