"""The event stream of a served instance (uvicorn, motionsim's WebSocket protocol, the fan-out)
sends what API.md's Events section says, byte for byte what the bus encodes.

API.md, Events: "first everything after ``since`` still held, then live, one JSON event per
message"; ``batch=true``: arrays of the events read together; a slow subscriber only falls
behind. Served here, a caught-up subscriber is written by its log's fan-out
(:mod:`motionsim.api.ws_fanout`) and handed back to its task for bursts and full buffers: the
streams below cross that boundary both ways and must not lose, repeat or reorder an event.
"""

from __future__ import annotations

import json
import socket

import httpx
from motionsim.api.ws_fanout import BATCH
from motionsim.api.ws_protocol import FramedWebSocketProtocol
from motionsim.app.embedded import EmbeddedService
from websockets.sync.client import connect

from tests.conftest import dummy_settings

#: uvicorn's transport high-water mark (asyncio's default for a socket transport: 64 KiB).
HIGH_WATER = 64 * 1024


def _served() -> EmbeddedService:
    return EmbeddedService(dummy_settings(port=0, pmac_port=0, trio_port=0))


def _ws(svc: EmbeddedService, query: str, **kw):
    url = svc.url.replace("http://", "ws://") + "/controllers/d/events?" + query
    return connect(url, compression=None, proxy=None, open_timeout=10, **kw)


def _advance(http: httpx.Client, seconds: float) -> None:
    http.post("/controllers/d/clock/advance", json={"seconds": seconds}).raise_for_status()


def _expected_texts(svc: EmbeddedService) -> list[str]:
    """The bus's text of every held event (the clock is virtual and idle: nothing emits)."""
    log = svc.app.state.registry.get("d").controller.log
    return [json.dumps(e.to_dict("d")) for e in log.events()]


def test_live_and_burst_events_arrive_once_each_in_order_as_the_bus_encodes_them():
    with _served() as svc, httpx.Client(base_url=svc.url, trust_env=False) as http, \
            _ws(svc, "since=0") as plain, _ws(svc, "since=0&type=tick&batch=true") as batched:
        assert json.loads(plain.recv(timeout=10))["type"] == "epoch"
        assert json.loads(batched.recv(timeout=10))[0]["type"] == "epoch"
        for _ in range(5):
            _advance(http, 0.02)  # two ticks each: the live path
        _advance(http, 0.01 * (BATCH * 3))  # a burst of three batches: back to the task
        for _ in range(3):
            _advance(http, 0.02)  # caught up again: live
        want = _expected_texts(svc)
        got = [plain.recv(timeout=10) for _ in want]
        arrays: list[dict] = []
        while len(arrays) < len(want):
            arrays.extend(json.loads(batched.recv(timeout=10)))
    assert got == want
    assert arrays == [json.loads(t) for t in want if '"type": "tick"' in t]


def test_a_client_that_does_not_read_holds_a_bounded_buffer_and_then_gets_every_event():
    with _served() as svc, httpx.Client(base_url=svc.url, trust_env=False) as http:
        sock = socket.socket()
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)  # the kernel holds little
        sock.connect((svc.settings.host, svc.port))
        port = sock.getsockname()[1]
        with _ws(svc, "since=0", sock=sock, max_queue=4) as slow, _ws(svc, "since=0") as fast:
            slow.recv(timeout=10)
            fast.recv(timeout=10)
            _advance(http, 0.02)  # both live
            _advance(http, 50.0)  # 5 000 ticks, ~400 KB: far beyond what the slow one takes
            n = len(_expected_texts(svc))
            fast_seqs = [json.loads(fast.recv(timeout=10))["seq"] for _ in range(n)]
            server_side = [c for c in svc._server.server_state.connections
                           if isinstance(c, FramedWebSocketProtocol) and c.client[1] == port]
            held = server_side[0].transport.get_write_buffer_size()
            slow_seqs = [json.loads(slow.recv(timeout=10))["seq"] for _ in range(n)]
    assert fast_seqs == list(range(1, n + 1))
    # one write beyond the high-water mark at most: a batch of ~80-byte events
    assert held <= HIGH_WATER + BATCH * 200
    assert slow_seqs == list(range(1, n + 1))
