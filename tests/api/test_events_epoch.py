"""The event log's ``epoch``: resume-by-seq knows which incarnation of the log it belongs to.

``seq`` restarts at 1 when a log is created again (a restart, a controller deleted and created
under the same id); a reader resuming with its old ``since`` must be told so (``reset``)
instead of getting silence.
"""

from __future__ import annotations

import json

import pytest
from fastapi.testclient import TestClient
from motionsim.api.main import create_app
from starlette.websockets import WebSocketDisconnect

from tests.conftest import dummy_settings

pytestmark = pytest.mark.anyio


async def _recreate(api) -> None:
    assert (await api.delete("/controllers/d")).status_code == 204
    r = await api.post("/controllers", json={"id": "d", "kind": "dummy",
                                             "clock": {"mode": "virtual"}})
    assert r.status_code == 201, r.text


async def test_every_page_names_the_log_epoch_and_it_is_stable(api):
    await api.post("/controllers/d/clock/advance", json={"seconds": 0.05})
    first = (await api.get("/controllers/d/events", params={"limit": 2})).json()
    more = (await api.get("/controllers/d/events", params={"since": first["next"]})).json()
    assert first["epoch"] == more["epoch"]
    await api.post("/controllers/d/reset")  # a power cycle keeps the log and its numbering
    after = (await api.get("/controllers/d/events", params={"since": more["next"]})).json()
    assert after["epoch"] == first["epoch"] and "reset" not in after


async def test_a_recreated_controller_has_a_new_epoch_and_a_stale_resume_is_reset(api):
    await api.post("/controllers/d/clock/advance", json={"seconds": 0.05})
    old = (await api.get("/controllers/d/events")).json()
    assert old["next"] == 5
    await _recreate(api)
    await api.post("/controllers/d/clock/advance", json={"seconds": 0.08})  # seq 1..8 again
    page = (await api.get("/controllers/d/events",
                          params={"since": old["next"], "epoch": old["epoch"]})).json()
    assert page["epoch"] != old["epoch"]
    assert page["reset"] == {"epoch": page["epoch"], "reason": "stale_epoch", "since": 5,
                             "last_seq": 8}
    assert [e["seq"] for e in page["events"]] == list(range(1, 9))  # from the start: no loss


async def test_a_since_beyond_the_end_of_the_log_is_reset_not_silence(api):
    await api.post("/controllers/d/clock/advance", json={"seconds": 0.03})
    page = (await api.get("/controllers/d/events", params={"since": 50})).json()
    assert page["reset"]["reason"] == "since_beyond_end"
    assert (page["reset"]["since"], page["reset"]["last_seq"]) == (50, 3)
    assert [e["seq"] for e in page["events"]] == [1, 2, 3]


async def test_the_current_epoch_resumes_normally(api):
    await api.post("/controllers/d/clock/advance", json={"seconds": 0.03})
    epoch = (await api.get("/controllers/d/events")).json()["epoch"]
    page = (await api.get("/controllers/d/events", params={"since": 2, "epoch": epoch})).json()
    assert "reset" not in page
    assert [e["seq"] for e in page["events"]] == [3]


async def test_an_unknown_event_type_is_422_naming_the_valid_ones(api):
    r = await api.get("/controllers/d/events", params=[("type", "tick"), ("type", "breqq")])
    assert r.status_code == 422
    body = r.json()
    assert (body["code"], body["field"]) == ("validation_error", "type")
    assert "'breqq'" in body["message"] and "breq" in body["valid"] and "tick" in body["valid"]
    assert "tick" in body["message"]


async def test_a_type_only_seen_in_the_log_is_valid(api, make_app):
    handle = api._transport.app.state.registry.get("d")
    handle.controller.log.emit("custom_kind_event")
    r = await api.get("/controllers/d/events", params={"type": "custom_kind_event"})
    assert r.status_code == 200 and len(r.json()["events"]) == 1


@pytest.fixture
def tc():
    # TestClient's WebSockets always send Host "testserver"
    with TestClient(create_app(dummy_settings(allowed_hosts=["testserver"]))) as client:
        yield client


def test_the_websocket_stream_starts_with_the_epoch(tc):
    tc.post("/controllers/d/clock/advance", json={"seconds": 0.02})
    epoch = tc.get("/controllers/d/events").json()["epoch"]
    with tc.websocket_connect("/controllers/d/events") as ws:
        hello = json.loads(ws.receive_text())
        first = json.loads(ws.receive_text())
    assert hello == {"type": "epoch", "epoch": epoch, "first_seq": 1, "last_seq": 2,
                     "reset": None}
    assert first["seq"] == 1


def test_a_websocket_resume_with_a_stale_epoch_is_reset_and_replays_the_new_log(tc):
    tc.post("/controllers/d/clock/advance", json={"seconds": 0.05})
    old_epoch = tc.get("/controllers/d/events").json()["epoch"]
    assert tc.delete("/controllers/d").status_code == 204
    tc.post("/controllers", json={"id": "d", "kind": "dummy", "clock": {"mode": "virtual"}})
    tc.post("/controllers/d/clock/advance", json={"seconds": 0.03})
    with tc.websocket_connect(f"/controllers/d/events?since=5&epoch={old_epoch}") as ws:
        hello = json.loads(ws.receive_text())
        events = [json.loads(ws.receive_text()) for _ in range(3)]
    assert hello["epoch"] != old_epoch
    assert hello["reset"] == {"epoch": hello["epoch"], "reason": "stale_epoch", "since": 5,
                              "last_seq": 3}
    assert [e["seq"] for e in events] == [1, 2, 3]


def test_a_websocket_with_an_unknown_event_type_is_closed_4422_naming_the_valid_ones(tc):
    with pytest.raises(WebSocketDisconnect) as exc, \
            tc.websocket_connect("/controllers/d/events?type=tick&type=nosuch") as ws:
        error = json.loads(ws.receive_text())
        ws.receive_text()
    assert exc.value.code == 4422
    assert exc.value.reason.startswith("unknown event type 'nosuch'; valid types: axis, breq")
    assert len(exc.value.reason.encode()) <= 123
    assert (error["type"], error["code"], error["field"]) == ("error", "validation_error", "type")
    assert {"tick", "breq", "line_loaded"} <= set(error["valid"])
