"""Ports for the servers tests start on 127.0.0.1."""

from __future__ import annotations

import random
import socket


def free_port() -> int:
    """A free 127.0.0.1 port for a server the test starts with it, taken below Linux's
    ephemeral range (32768-60999): a port the kernel handed out and took back could be given
    to some outgoing connection before the server binds it ("address already in use"); one
    below the range is only ever taken by an explicit bind."""
    rng = random.SystemRandom()
    for _ in range(200):
        port = rng.randrange(20000, 32768)
        with socket.socket() as s:
            try:
                s.bind(("127.0.0.1", port))
            except OSError:
                continue
            return port
    raise RuntimeError("no free port in 20000-32767")
