"""Connection limits cannot lock out ``/health`` or REST (issue 33 item 5; api/http_limits.py).

800 idle WebSocket subscribers used to make every REST client, ``/health`` included, get 503
(a container health check would then restart the service). Now WebSockets may take at most
3/4 of ``http_max_connections``; past the cap ``HEALTH_RESERVE`` connections may still ask
``GET /health``; and a connection whose descriptor is near the process's limit is refused
before the operating system refuses ``accept``. Served for real with a small cap; counts and
statuses only.
"""

from __future__ import annotations

import json
import socket
import time
from collections.abc import Iterator

import pytest
from motionsim.api import http_limits
from motionsim.api.http_limits import HEALTH_RESERVE, websocket_cap
from motionsim.app.embedded import EmbeddedService
from motionsim.app.settings import Settings

CAP = 8
UPGRADE = (b"GET /controllers/p/events HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\n"
           b"Connection: Upgrade\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
           b"Sec-WebSocket-Version: 13\r\n\r\n")


@pytest.fixture
def served() -> Iterator[EmbeddedService]:
    settings = Settings(port=0, clock={"mode": "virtual"}, pmac_port=0, trio_port=0,
                        controllers=[{"id": "p", "kind": "pmac"}], http_max_connections=CAP,
                        http_header_timeout_s=5.0)
    with EmbeddedService(settings) as service:
        yield service


def _connect(service: EmbeddedService) -> socket.socket:
    return socket.create_connection(("127.0.0.1", service.port), timeout=5)


def _head(sock: socket.socket) -> bytes:
    got = b""
    while b"\r\n\r\n" not in got:
        chunk = sock.recv(4096)
        if not chunk:
            break
        got += chunk
    return got


def _ask(service: EmbeddedService, path: str) -> tuple[int, bytes]:
    with _connect(service) as s:
        s.sendall(f"GET {path} HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n"
                  .encode())
        got = b""
        while True:
            chunk = s.recv(65536)
            if not chunk:
                break
            got += chunk
    return int(got.split(b" ", 2)[1]), got.partition(b"\r\n\r\n")[2]


def test_the_pool_shares() -> None:
    assert websocket_cap(800) == 600 and websocket_cap(CAP) == 6 and HEALTH_RESERVE == 32


def test_websockets_cannot_take_the_rest_clients_share(served):
    subscribers = []
    try:
        for _ in range(websocket_cap(CAP)):
            s = _connect(served)
            s.sendall(UPGRADE)
            assert _head(s).startswith(b"HTTP/1.1 101")
            subscribers.append(s)
        one_more = _connect(served)
        one_more.sendall(UPGRADE)
        head = _head(one_more)
        one_more.close()
        assert head.startswith(b"HTTP/1.1 503")
        assert b"too_many_websockets" in head or b"too_many_websockets" in one_more.recv(0)
        # REST is still served beside the full WebSocket pool
        assert _ask(served, "/controllers")[0] == 200
        assert _ask(served, "/health")[0] == 200
    finally:
        for s in subscribers:
            s.close()


def test_past_the_cap_health_is_answered_and_other_requests_refused(served):
    held = [_connect(served) for _ in range(CAP)]
    try:
        for s in held:
            s.sendall(b"GET /health HTTP/1.1\r\nHost: x\r\n")  # half-sent: stays open
        time.sleep(0.2)
        assert _ask(served, "/health")[0] == 200
        status, body = _ask(served, "/controllers")
        assert status == 503 and json.loads(body)["code"] == "too_many_connections"
        # past the /health reserve as well: refused at once
        extra = [_connect(served) for _ in range(HEALTH_RESERVE)]
        time.sleep(0.2)
        with _connect(served) as late:  # answered before it sends anything
            got = _head(late)
            got += late.recv(4096)
        assert got.startswith(b"HTTP/1.1 503") and b'"limit": 8' in got
        for s in extra:
            s.close()
    finally:
        for s in held:
            s.close()
    time.sleep(0.2)
    assert _ask(served, "/controllers")[0] == 200


def test_a_connection_near_the_descriptor_limit_is_refused_before_the_os_does(
        served, monkeypatch):
    monkeypatch.setattr(http_limits, "_FD_CEILING", 3)  # every new descriptor is over it
    with _connect(served) as s:
        got = _head(s)
        got += s.recv(4096)
    assert got.startswith(b"HTTP/1.1 503")
    answer = json.loads(got.partition(b"\r\n\r\n")[2])
    assert answer["code"] == "too_many_connections" and "file-descriptor" in answer["message"]
    monkeypatch.undo()
    assert _ask(served, "/health")[0] == 200
