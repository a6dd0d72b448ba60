"""The service's own listening sockets."""

from __future__ import annotations

import socket

import pytest
from motionsim.app.sockets import bind_tcp


def test_bound_socket_is_tcp_so_connections_get_nodelay():
    sock = bind_tcp("127.0.0.1", 0)
    try:
        assert sock.proto == socket.IPPROTO_TCP
        assert sock.getsockname()[1] > 0
        assert not sock.getblocking()
    finally:
        sock.close()


def test_a_port_in_use_raises_oserror():
    busy = bind_tcp("127.0.0.1", 0)
    try:
        busy.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 0)
        with pytest.raises(OSError):
            bind_tcp("127.0.0.1", busy.getsockname()[1])
    finally:
        busy.close()
