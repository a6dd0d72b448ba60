"""The documented WebSocket close codes are what a real ``websockets`` client sees.

Against a ``motionsim serve`` subprocess: the server accepts the handshake and then closes with
4404 (unknown controller), 4422 (bad query: an unknown event type, a negative ``since``) or
4410 (the controller was deleted while streaming), each with a reason (API.md, Events).
A close before the handshake would reach the client as a bare HTTP 403 with no reason.
"""

from __future__ import annotations

import json

import httpx
import pytest
from websockets.exceptions import ConnectionClosed
from websockets.sync.client import connect

from tests.integration.test_clients_pmac import motionsim_serve


@pytest.fixture(scope="module")
def svc():
    with motionsim_serve("--pmac-port", "0", "--trio-port", "0") as service:
        yield service


def _ws(svc, path: str):
    return connect(svc.http.replace("http://", "ws://") + path, compression=None, proxy=None,
                   open_timeout=10)


def _close_of(ws) -> tuple[int, str, list[dict]]:
    """Read until the server closes; the close code, reason and the messages before it."""
    messages = []
    with pytest.raises(ConnectionClosed) as exc:
        while True:
            messages.append(json.loads(ws.recv(timeout=10)))
    assert exc.value.rcvd is not None, "the server sent no close frame"
    return exc.value.rcvd.code, exc.value.rcvd.reason, messages


def test_an_unknown_controller_is_closed_4404_with_a_reason(svc):
    with _ws(svc, "/controllers/nope/events") as ws:
        code, reason, messages = _close_of(ws)
    assert (code, messages) == (4404, [])
    assert "no controller 'nope'" in reason


def test_an_unknown_event_type_is_closed_4422_naming_the_valid_ones(svc):
    with _ws(svc, "/controllers/pmac/events?type=breq&type=bogus") as ws:
        code, reason, messages = _close_of(ws)
    assert code == 4422
    assert reason.startswith("unknown event type 'bogus'; valid types:")
    assert messages[0]["code"] == "validation_error"
    assert {"breq", "line_loaded", "move_start"} <= set(messages[0]["valid"])


def test_a_negative_since_is_closed_4422(svc):
    with _ws(svc, "/controllers/pmac/events?since=-3") as ws:
        code, reason, _ = _close_of(ws)
    assert (code, reason) == (4422, "since must be >= 0")


def test_deleting_the_controller_closes_its_stream_4410(svc):
    with _ws(svc, "/controllers/trio/events") as ws:
        hello = json.loads(ws.recv(timeout=10))
        assert hello["type"] == "epoch"
        assert httpx.delete(svc.http + "/controllers/trio", timeout=10).status_code == 204
        code, reason, _ = _close_of(ws)
    assert (code, reason) == (4410, "controller deleted")


def test_a_memory_error_ends_the_process_so_a_supervisor_restarts_it(tmp_path):
    import subprocess

    config = tmp_path / "settings.json"
    config.write_text(json.dumps({"plugins": ["tests.dummy_kind"], "controllers": [
        {"id": "d", "kind": "dummy", "clock": {"mode": "virtual"}}]}))
    with motionsim_serve("--pmac-port", "0", "--trio-port", "0", "--config", str(config)) as s:
        with pytest.raises(httpx.HTTPError):
            httpx.post(s.http + "/controllers/d/terminal", json={"command": "OOM"}, timeout=10)
        try:
            code = s.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            pytest.fail("the service stayed alive after a MemoryError")
    assert code == 3


def test_the_token_guards_rest_and_websocket_of_a_served_instance():
    with motionsim_serve("--pmac-port", "0", "--trio-port", "0", "--token", "t0k") as s:
        assert httpx.get(s.http + "/health", timeout=10).status_code == 200
        assert httpx.get(s.http + "/controllers", timeout=10).status_code == 401
        assert httpx.get(s.http + "/controllers", headers={"authorization": "Bearer t0k"},
                         timeout=10).status_code == 200
        with _ws(s, "/controllers/pmac/events") as ws:
            code, _, _ = _close_of(ws)
        assert code == 4401
        with _ws(s, "/controllers/pmac/events?token=t0k") as ws:
            assert json.loads(ws.recv(timeout=10))["type"] == "epoch"


@pytest.mark.parametrize("query,field", [("since=abc", "since"), ("since=1.5", "since"),
                                         ("batch=maybe", "batch"),
                                         ("since=99999999999999999999", "since"),
                                         ("epoch=" + "e" * 65, "epoch")])
def test_a_query_fastapi_would_refuse_before_the_handshake_is_closed_4422(svc, query, field):
    """Issue 23, item 5: accepted, then closed 4422 with a reason naming the field — not an
    HTTP 403 at the handshake (which reads as the Origin refusal)."""
    with _ws(svc, f"/controllers/pmac/events?{query}") as ws:
        code, reason, messages = _close_of(ws)
    assert code == 4422
    assert reason.startswith(f"query field {field!r}:")
    (error,) = messages
    assert (error["type"], error["code"], error["field"]) == ("error", "validation_error", field)


def test_a_good_query_still_streams(svc):
    with _ws(svc, "/controllers/pmac/events?since=0&batch=true&type=breq") as ws:
        first = json.loads(ws.recv(timeout=10))
    assert isinstance(first, list) and first[0]["type"] == "epoch"
