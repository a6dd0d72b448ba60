"""The HTTP port's own limits (issue 23, item 3): connection cap, header time-out, header
size, and a readable 413 for an over-limit body — each refusal a JSON body naming its setting.

Served for real (uvicorn on 127.0.0.1, port 0) with small limits, and probed with raw sockets
the way the attacks were made: half-sent requests, idle sockets, oversized headers.
"""

from __future__ import annotations

import http.client
import json
import socket
import time
from collections.abc import Iterator

import httpx
import pytest
from motionsim.app.embedded import EmbeddedService
from motionsim.app.settings import Settings

LIMITS = {"http_max_connections": 4, "http_header_timeout_s": 0.5,
          "http_max_header_bytes": 2048, "max_body_bytes": 4096}


@pytest.fixture(scope="module")
def served() -> Iterator[EmbeddedService]:
    settings = Settings(port=0, clock={"mode": "virtual"}, pmac_port=0, trio_port=0,
                        controllers=[{"id": "p", "kind": "pmac"}], **LIMITS)
    with EmbeddedService(settings) as service:
        yield service


def _connect(service: EmbeddedService) -> socket.socket:
    return socket.create_connection(("127.0.0.1", service.port), timeout=5)


def _read_all(sock: socket.socket) -> bytes:
    got = b""
    while True:
        try:
            chunk = sock.recv(65536)
        except ConnectionResetError:
            return got
        if not chunk:
            return got
        got += chunk


def _response(raw: bytes) -> tuple[int, dict]:
    head, _, body = raw.partition(b"\r\n\r\n")
    status = int(head.split(b" ", 2)[1])
    return status, json.loads(body)


def _health(service: EmbeddedService) -> int:
    return httpx.get(f"{service.url}/health", timeout=5, trust_env=False).status_code


def test_a_request_whose_headers_never_finish_gets_408_and_is_closed(served):
    sock = _connect(served)
    try:
        sock.sendall(b"GET /health HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ")
        started = time.monotonic()
        status, body = _response(_read_all(sock))
        waited = time.monotonic() - started
    finally:
        sock.close()
    assert status == 408 and body["code"] == "request_timeout"
    assert body["limit"] == 0.5 and "http_header_timeout_s" in body["message"]
    assert waited < 4.0
    assert _health(served) == 200


def test_a_connection_that_sends_nothing_is_closed_after_the_header_timeout(served):
    sock = _connect(served)
    try:
        status, body = _response(_read_all(sock))
    finally:
        sock.close()
    assert status == 408 and body["code"] == "request_timeout"


def test_request_headers_over_the_limit_get_431_naming_it(served):
    sock = _connect(served)
    try:
        sock.sendall(b"GET /health HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Big: " + b"a" * 3000
                     + b"\r\n\r\n")
        status, body = _response(_read_all(sock))
    finally:
        sock.close()
    assert status == 431 and body["code"] == "headers_too_large"
    assert body["limit"] == 2048 and "http_max_header_bytes" in body["message"]


def test_a_header_that_never_ends_is_refused_once_over_the_limit(served):
    sock = _connect(served)
    try:
        sock.sendall(b"GET /health HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Big: ")
        for _ in range(10):
            try:
                sock.sendall(b"a" * 1000)
            except (BrokenPipeError, ConnectionResetError):
                break  # refused part-way: the answer is already waiting
        status, body = _response(_read_all(sock))
    finally:
        sock.close()
    assert status == 431 and body["code"] == "headers_too_large"


def test_headers_under_the_limit_are_served(served):
    r = httpx.get(f"{served.url}/health", headers={"X-Fine": "a" * 1500}, timeout=5,
                  trust_env=False)
    assert r.status_code == 200


def test_over_the_connection_cap_a_new_connection_gets_503_and_is_closed(served):
    idle = [_connect(served) for _ in range(4)]
    try:
        time.sleep(0.1)
        extra = _connect(served)
        try:
            status, body = _response(_read_all(extra))
        finally:
            extra.close()
        assert status == 503 and body["code"] == "too_many_connections"
        assert body["limit"] == 4 and "http_max_connections" in body["message"]
    finally:
        for sock in idle:
            sock.close()
    time.sleep(0.1)
    assert _health(served) == 200


@pytest.mark.parametrize("size", [100_000, 2_000_000, 20_000_000])
def test_an_over_limit_body_with_content_length_gets_a_readable_413(served, size):
    """``http.client`` (under ``requests``) sends its whole body before it reads: it must
    read the 413, not fail on a broken pipe or a reset."""
    body = b'{"lines": ["' + b"X" * size + b'"]}'
    conn = http.client.HTTPConnection("127.0.0.1", served.port, timeout=10)
    try:
        conn.request("POST", "/controllers/p/coord/1/rotary/lines", body=body,
                     headers={"content-type": "application/json"})
        response = conn.getresponse()
        status, answer = response.status, json.loads(response.read())
    finally:
        conn.close()
    assert status == 413
    assert answer["code"] == "body_too_large" and answer["limit"] == 4096
    assert str(len(body)) in answer["message"] and "max_body_bytes" in answer["message"]
    assert _health(served) == 200


def test_connections_refused_over_the_cap_never_refuse_an_admitted_clients_requests():
    """Issue 23 item 4's rule on the HTTP port: a flood of connections over the cap is refused
    at the door; a client already connected (the real host, on its keep-alive connection)
    keeps being served — a refused connection no longer counts as open while it closes."""
    import threading

    settings = Settings(port=0, clock={"mode": "virtual"}, pmac_port=0, trio_port=0,
                        controllers=[], http_max_connections=3, http_header_timeout_s=30.0)
    with EmbeddedService(settings) as service:
        host = http.client.HTTPConnection("127.0.0.1", service.port, timeout=5)
        host.request("GET", "/health")
        assert host.getresponse().read() and True
        stuck = [_connect(service) for _ in range(2)]  # the cap is now full
        for s in stuck:
            s.sendall(b"GET /health HTTP/1.1\r\nHost: x\r\n")
        stop = threading.Event()

        def flood() -> None:
            while not stop.is_set():
                with socket.create_connection(("127.0.0.1", service.port), timeout=5) as s:
                    s.recv(1024)

        floods = [threading.Thread(target=flood) for _ in range(4)]
        for t in floods:
            t.start()
        statuses = []
        try:
            for _ in range(200):
                host.request("GET", "/health")
                r = host.getresponse()
                r.read()
                statuses.append(r.status)
        finally:
            stop.set()
            for t in floods:
                t.join()
            for s in stuck:
                s.close()
            host.close()
    assert set(statuses) == {200}, statuses.count(503)
