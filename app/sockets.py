"""Listening sockets the service binds itself (so ``--port 0`` can report the port chosen)."""

from __future__ import annotations

import socket


def bind_tcp(host: str, port: int, backlog: int = 2048) -> socket.socket:
    """A non-blocking TCP socket listening on ``host:port`` (``port`` 0 = a free port).

    The socket is created with ``IPPROTO_TCP`` explicitly: asyncio sets ``TCP_NODELAY`` only on
    sockets whose ``proto`` says TCP, and accepted connections inherit it. Without it every
    HTTP response waits ~40 ms (Nagle's algorithm against the client's delayed ACK).

    Raises:
        OSError: the address cannot be bound.
    """
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    sock = socket.socket(family, socket.SOCK_STREAM, socket.IPPROTO_TCP)
    try:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        sock.bind((host, port))
        sock.listen(backlog)
        sock.setblocking(False)
    except OSError:
        sock.close()
        raise
    return sock


__all__ = ["bind_tcp"]
