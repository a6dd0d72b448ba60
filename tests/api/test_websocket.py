"""WebSocket /controllers/{id}/events: backlog, live, resume by seq, gaps, filters."""

from __future__ import annotations

import json
import threading

import pytest
from fastapi.testclient import TestClient
from motionsim.api.main import create_app
from starlette.websockets import WebSocketDisconnect

from tests.conftest import dummy_settings


@pytest.fixture
def tc():
    app = create_app(dummy_settings(allowed_hosts=["testserver"]))
    with TestClient(app) as client:
        yield client


def _recv(ws, n):
    return [json.loads(ws.receive_text()) for _ in range(n)]


def _hello(ws):
    """The stream's first message: the log's epoch."""
    msg = json.loads(ws.receive_text())
    assert msg["type"] == "epoch", msg
    return msg


def test_backlog_then_live_events_one_json_event_per_message(tc):
    tc.post("/controllers/d/clock/advance", json={"seconds": 0.03})
    with tc.websocket_connect("/controllers/d/events") as ws:
        _hello(ws)
        backlog = _recv(ws, 3)
        assert [(e["seq"], e["type"], e["n"], e["controller"]) for e in backlog] == [
            (1, "tick", 1, "d"), (2, "tick", 2, "d"), (3, "tick", 3, "d")]
        tc.post("/controllers/d/clock/advance", json={"seconds": 0.02})
        live = _recv(ws, 2)
        assert [(e["seq"], e["t"]) for e in live] == [(4, pytest.approx(0.04)),
                                                     (5, pytest.approx(0.05))]


def test_reconnect_with_last_seq_resumes_without_gaps_or_duplicates(tc):
    seen = []
    tc.post("/controllers/d/clock/advance", json={"seconds": 0.05})
    with tc.websocket_connect("/controllers/d/events?since=0") as ws:
        _hello(ws)
        seen += _recv(ws, 3)
    # disconnected: more events happen meanwhile
    tc.post("/controllers/d/clock/advance", json={"seconds": 0.05})
    with tc.websocket_connect(f"/controllers/d/events?since={seen[-1]['seq']}") as ws:
        _hello(ws)
        seen += _recv(ws, 7)
        tc.post("/controllers/d/clock/advance", json={"seconds": 0.02})
        seen += _recv(ws, 2)
    assert [e["seq"] for e in seen] == list(range(1, 13))
    assert [e["n"] for e in seen] == list(range(1, 13))


def test_type_filter(tc):
    tc.post("/controllers/d/clock/advance", json={"seconds": 0.02})
    tc.put("/controllers/d/variables/V1", json={"value": 1})
    with tc.websocket_connect("/controllers/d/events?type=var&type=ping") as ws:
        _hello(ws)
        assert _recv(ws, 1)[0]["seq"] == 3
        tc.post("/controllers/d/clock/advance", json={"seconds": 0.02})
        tc.post("/controllers/d/terminal", json={"command": "PING p"})
        msg = _recv(ws, 1)[0]
        assert (msg["type"], msg["seq"], msg["text"]) == ("ping", 6, "p")


def test_a_subscriber_behind_the_ring_gets_a_gap_message_first(tc):
    log = tc.app.state.registry.get("d").controller.log
    for i in range(log.capacity + 5):
        log.emit("fill", i=i)
    with tc.websocket_connect("/controllers/d/events?since=2") as ws:
        _hello(ws)
        first, second = _recv(ws, 2)
    assert first == {"type": "gap", "from": 3, "to": 5}
    assert second["seq"] == 6


def test_unknown_controller_closes_with_4404(tc):
    with pytest.raises(WebSocketDisconnect) as exc, \
            tc.websocket_connect("/controllers/nope/events") as ws:
        ws.receive_text()
    assert exc.value.code == 4404


def test_a_slow_subscriber_does_not_block_the_simulation_or_others(tc):
    """One subscriber never reads; another reads everything; the sim keeps going."""
    with tc.websocket_connect("/controllers/d/events") as slow, \
            tc.websocket_connect("/controllers/d/events") as fast:
        _hello(slow)
        _hello(fast)
        got = []
        done = threading.Event()

        def reader():
            while len(got) < 2000:
                got.append(json.loads(fast.receive_text()))
            done.set()

        th = threading.Thread(target=reader, daemon=True)
        th.start()
        r = tc.post("/controllers/d/clock/advance", json={"seconds": 20.0})
        assert r.json()["t"] == pytest.approx(20.0)
        assert done.wait(20)
        assert [e["seq"] for e in got] == list(range(1, 2001))
        assert json.loads(slow.receive_text())["seq"] == 1


def test_live_events_of_a_realtime_controller_arrive_without_any_request():
    app = create_app(dummy_settings(allowed_hosts=["testserver"], controllers=[
        {"id": "rt", "kind": "dummy", "clock": {"mode": "realtime", "factor": 1},
         "config": {"tick_s": 0.02}}]))
    with TestClient(app) as tc, tc.websocket_connect("/controllers/rt/events?type=tick") as ws:
        _hello(ws)
        got = _recv(ws, 5)
    assert [e["n"] for e in got] == [1, 2, 3, 4, 5]
    assert [e["t"] for e in got] == pytest.approx([0.02, 0.04, 0.06, 0.08, 0.1])


def test_deleting_the_controller_closes_its_streams_with_4410(tc):
    with tc.websocket_connect("/controllers/d/events") as ws:
        _hello(ws)
        tc.post("/controllers/d/clock/advance", json={"seconds": 0.01})
        assert _recv(ws, 1)[0]["seq"] == 1
        assert tc.delete("/controllers/d").status_code == 204
        with pytest.raises(WebSocketDisconnect) as exc:
            ws.receive_text()
    assert exc.value.code == 4410


def test_batch_mode_sends_arrays_of_events(tc):
    tc.post("/controllers/d/clock/advance", json={"seconds": 0.03})
    with tc.websocket_connect("/controllers/d/events?batch=true") as ws:
        hello, *first = json.loads(ws.receive_text())
        assert hello["type"] == "epoch"
        assert [e["seq"] for e in first] == [1, 2, 3]
        tc.post("/controllers/d/clock/advance", json={"seconds": 0.02})
        seen = []
        while len(seen) < 2:
            seen += json.loads(ws.receive_text())
    assert [e["seq"] for e in seen] == [4, 5]
