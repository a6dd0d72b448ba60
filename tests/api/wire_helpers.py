"""One loopback set-up for the wire-protocol tests: a controller on a virtual clock, served by a
protocol server (``serve_pmac``, ``serve_trio``, ``serve_modbus``) on 127.0.0.1, an OS-chosen
port, torn down in the order the servers need (server, then recorder, then registry)."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator, Awaitable, Callable
from contextlib import asynccontextmanager
from pathlib import Path
from typing import Any, NamedTuple, TypeVar

from motionsim.app.recorder import Recorder
from motionsim.app.registry import ControllerHandle, Registry

import tests.api.wire_standins  # noqa: F401 - registers the stand-in kinds

T = TypeVar("T")
Serve = Callable[..., Awaitable[asyncio.Server]]


class Served(NamedTuple):
    handle: ControllerHandle
    port: int


@asynccontextmanager
async def serving(serve: Serve, kind: str, id: str, *,
                  record_to: Path | None = None) -> AsyncIterator[Served]:
    """A ``kind`` controller ``id`` on a virtual clock, served on loopback; with ``record_to``
    the connections are written to that transcript file."""
    registry = Registry()
    handle = registry.add(kind, id, clock="virtual")
    recorder = Recorder.for_handles(record_to, [handle]) if record_to is not None else None
    extra: dict[str, Any] = {"recorder": recorder} if recorder is not None else {}
    server = await serve(handle, "127.0.0.1", 0, **extra)
    try:
        yield Served(handle, server.sockets[0].getsockname()[1])
    finally:
        server.close()
        await server.wait_closed()
        if recorder is not None:
            recorder.close()
        await registry.close()


def run_served(serve: Serve, kind: str, id: str,
               scenario: Callable[[ControllerHandle, int], Awaitable[T]]) -> T:
    """Run ``scenario(handle, port)`` against a served controller, in a fresh event loop."""

    async def main() -> T:
        async with serving(serve, kind, id) as (handle, port):
            return await scenario(handle, port)

    return asyncio.run(main())


async def connect(port: int) -> tuple[asyncio.StreamReader, asyncio.StreamWriter]:
    """A plain TCP client connection to the loopback server."""
    return await asyncio.open_connection("127.0.0.1", port)
