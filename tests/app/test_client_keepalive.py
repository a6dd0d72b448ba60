"""MotionSimClient survives the server's keep-alive close (issue 36 item 2).

A pooled connection reused just as the server's keep-alive timer closes it fails with
``Server disconnected without sending a response``. The server here is a plain socket that
does exactly that, deterministically: it answers the first request on a connection with
``Connection: keep-alive`` and closes the connection when the next request arrives on it,
without answering. An idempotent request is then sent once more, on a new connection; a POST
is not (the server may have acted on it). RFC 9110 §9.2.2 names the idempotent methods.
"""

from __future__ import annotations

import socket
import threading
from collections.abc import Iterator

import httpx
import pytest
from motionsim.app.client import KEEPALIVE_EXPIRY_S, MotionSimClient
from motionsim.app.settings import Settings

BODY = b'{"name": "I16", "value": 5}'
ANSWER = (b"HTTP/1.1 200 OK\r\nContent-Type: application/json\r\nConnection: keep-alive\r\n"
          b"Content-Length: " + str(len(BODY)).encode() + b"\r\n\r\n" + BODY)


class ClosingServer:
    """Answers one request per connection, then drops the connection on the next one."""

    def __init__(self) -> None:
        self.sock = socket.create_server(("127.0.0.1", 0))
        self.port = self.sock.getsockname()[1]
        self.connections = 0
        self.requests: list[bytes] = []   # request lines that were answered
        self.dropped: list[bytes] = []    # request lines the connection was closed under
        threading.Thread(target=self._serve, daemon=True).start()

    def _serve(self) -> None:
        while True:
            try:
                conn, _ = self.sock.accept()
            except OSError:
                return
            self.connections += 1
            threading.Thread(target=self._one, args=(conn,), daemon=True).start()

    def _read_request(self, conn: socket.socket) -> bytes | None:
        data = b""
        while b"\r\n\r\n" not in data:
            chunk = conn.recv(65536)
            if not chunk:
                return None
            data += chunk
        head, _, rest = data.partition(b"\r\n\r\n")
        length = next((int(h.split(b":")[1]) for h in head.split(b"\r\n")
                       if h.lower().startswith(b"content-length:")), 0)
        while len(rest) < length:
            rest += conn.recv(65536)
        return head.split(b"\r\n")[0]

    def _one(self, conn: socket.socket) -> None:
        with conn:
            first = self._read_request(conn)
            if first is None:
                return
            self.requests.append(first)
            conn.sendall(ANSWER)
            second = self._read_request(conn)
            if second is not None:
                self.dropped.append(second)   # closed under it: no response at all

    def close(self) -> None:
        self.sock.close()


@pytest.fixture
def server() -> Iterator[ClosingServer]:
    s = ClosingServer()
    yield s
    s.close()


def test_an_idempotent_request_on_a_connection_closed_under_it_is_sent_again(server):
    with MotionSimClient(f"http://127.0.0.1:{server.port}") as ms:
        assert ms.get_variable("p", "I16") == 5
        assert ms.get_variable("p", "I16") == 5   # reused connection dropped, then retried
        assert ms.set_variable("p", "I16", 5) == 5  # PUT is idempotent too
    assert server.dropped == [b"GET /controllers/p/variables/I16 HTTP/1.1",
                              b"PUT /controllers/p/variables/I16 HTTP/1.1"]
    assert server.requests == [b"GET /controllers/p/variables/I16 HTTP/1.1"] * 2 + [
        b"PUT /controllers/p/variables/I16 HTTP/1.1"]
    assert server.connections == 3


def test_a_post_is_never_sent_twice(server):
    with MotionSimClient(f"http://127.0.0.1:{server.port}") as ms:
        ms.get_variable("p", "I16")
        with pytest.raises(httpx.RemoteProtocolError):
            ms.request("POST", "/controllers/p/clock/advance", json={"seconds": 1.0})
    assert server.dropped == [b"POST /controllers/p/clock/advance HTTP/1.1"]
    assert server.requests == [b"GET /controllers/p/variables/I16 HTTP/1.1"]


def test_a_second_failure_is_raised_not_retried_again():
    """Nothing listens: the one retry fails too and the error reaches the caller."""
    sock = socket.create_server(("127.0.0.1", 0))
    port = sock.getsockname()[1]
    sock.close()
    with MotionSimClient(f"http://127.0.0.1:{port}") as ms, pytest.raises(httpx.ConnectError):
        ms.get_variable("p", "I16")


def test_the_pool_drops_idle_connections_before_the_server_closes_them():
    """The client's keep-alive expiry is shorter than the server's default keep-alive, so in
    the ordinary case the race above does not even happen."""
    assert Settings().http_keep_alive_s > KEEPALIVE_EXPIRY_S
    with MotionSimClient("http://127.0.0.1:1") as ms:
        pool = ms.http._transport._pool  # httpx's connection pool (httpcore)
        assert pool._keepalive_expiry == KEEPALIVE_EXPIRY_S
