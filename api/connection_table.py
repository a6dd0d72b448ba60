"""The open connections of one TCP protocol listener, and who makes room when it is full.

A real host must never be locked out of the PMAC / Trio port by sockets a crashed or stuck
client left open. The listener holds at most ``max_connections``; when one more arrives, the
connection **idle the longest** (no bytes received from its host for the longest time, and no
command of it waiting for the controller) is closed to make room, and the newcomer is served.
Only when every open connection is in the middle of a command is the newcomer closed at once
[INF: the manuals say nothing of a connection limit; the real PMAC Ethernet card serves a few
sockets and drops the oldest, which this policy resembles].

The connection served by the current task is found with :func:`current_connection`, so the
read loop can mark it active and the reply loop busy without threading the entry through
every protocol's code.
"""

from __future__ import annotations

import asyncio
import contextlib
import contextvars
import logging
import time
from collections.abc import Iterator

log = logging.getLogger("motionsim.wire")


class Connection:
    """One open connection: when its host last sent bytes, and whether it waits on a reply."""

    __slots__ = ("writer", "last_active", "busy")

    def __init__(self, writer: asyncio.StreamWriter) -> None:
        self.writer = writer
        self.last_active = time.monotonic()
        self.busy = 0

    def touch(self) -> None:
        self.last_active = time.monotonic()

    @contextlib.contextmanager
    def working(self) -> Iterator[None]:
        """Mark the connection busy (not to be evicted) while its commands run."""
        self.busy += 1
        try:
            yield
        finally:
            self.busy -= 1
            self.touch()


_CURRENT: contextvars.ContextVar[Connection | None] = contextvars.ContextVar(
    "motionsim_connection", default=None)


def current_connection() -> Connection | None:
    """The :class:`Connection` the running task serves (None outside a listener)."""
    return _CURRENT.get()


class ConnectionTable:
    """At most ``max_connections`` open; the idlest makes room for a newcomer."""

    def __init__(self, max_connections: int, name: str = "tcp") -> None:
        self.max_connections = max_connections
        self.name = name
        self._open: list[Connection] = []
        self.evicted = 0

    def __len__(self) -> int:
        return len(self._open)

    def admit(self, writer: asyncio.StreamWriter) -> Connection | None:
        """Register ``writer``'s connection, closing the idlest one if full; None (refused)
        when every open connection is busy."""
        if len(self._open) >= self.max_connections:
            idle = [c for c in self._open if not c.busy]
            if not idle:
                return None
            victim = min(idle, key=lambda c: c.last_active)
            self._open.remove(victim)
            self.evicted += 1
            log.warning("%s: %d connections open (setting tcp_max_connections); closing the "
                        "one idle for %.1f s to make room", self.name, self.max_connections,
                        time.monotonic() - victim.last_active)
            victim.writer.close()
        connection = Connection(writer)
        self._open.append(connection)
        _CURRENT.set(connection)
        return connection

    def release(self, connection: Connection) -> None:
        with contextlib.suppress(ValueError):
            self._open.remove(connection)


__all__ = ["Connection", "ConnectionTable", "current_connection"]
