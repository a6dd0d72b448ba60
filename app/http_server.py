"""The ``uvicorn.Config`` both ``motionsim serve`` and the embedded service run HTTP with."""

from __future__ import annotations

import asyncio
import gc
from collections.abc import Callable, Coroutine
from typing import Any, TypeVar

from .settings import Settings


def uvicorn_config(app: Any, settings: Settings, *, graceful_s: float) -> Any:
    """A ``uvicorn.Config`` for ``app`` with the HTTP port's limits from ``settings``
    (:mod:`motionsim.api.http_limits`)."""
    import uvicorn

    from ..api.http_limits import HttpLimits, uvicorn_limits
    from ..api.ws_protocol import FramedWebSocketProtocol

    limits = HttpLimits(max_connections=settings.http_max_connections,
                        header_timeout_s=settings.http_header_timeout_s,
                        max_header_bytes=settings.http_max_header_bytes,
                        keep_alive_s=settings.http_keep_alive_s)
    # the event stream's fan-out writes ready-made frames (motionsim.api.ws_protocol)
    return uvicorn.Config(app, log_level="warning", ws=FramedWebSocketProtocol,
                          ws_per_message_deflate=False,
                          lifespan="on", timeout_graceful_shutdown=graceful_s,
                          **uvicorn_limits(limits))


T = TypeVar("T")


def loop_factory(choice: str) -> Callable[[], asyncio.AbstractEventLoop] | None:
    """The event loop the service runs on (setting ``event_loop``): ``"uvloop"`` (libuv:
    its sockets, timers and polling in C — the loop uvicorn itself would pick), ``"asyncio"``
    (the standard library's), ``"auto"`` = uvloop when it is installed (``uvicorn[standard]``
    brings it). ``None``: the standard loop.

    Raises:
        ImportError: ``"uvloop"`` asked for and not installed.
    """
    if choice == "asyncio":
        return None
    try:
        import uvloop
    except ImportError:
        if choice == "uvloop":
            raise
        return None
    return uvloop.new_event_loop


def run_service(main: Coroutine[Any, Any, T], event_loop: str) -> T:
    """Run the service's coroutine ``main`` to its end on a new event loop of the kind
    ``event_loop`` (the setting) names (:func:`loop_factory`), in the calling thread."""
    with asyncio.Runner(loop_factory=loop_factory(event_loop)) as runner:
        return runner.run(main)


def freeze_startup_heap() -> None:
    """Collect, then freeze (``gc.freeze``) the objects the start-up made — modules, the app,
    its routes and schemas, the controllers: hundreds of thousands, alive for the whole run.

    Left to the cyclic collector, every full pass walks them all again: ~75 ms of the event
    loop here, a pause every realtime clock and WebSocket subscriber sees (issue 35: one such
    pass inside a 4-s window is the realtime clock's lateness p99 at 250 events/s). Frozen,
    a full pass walks only what was made since. Called once, before serving; the collect
    first, so that no start-up garbage is frozen with them. ``motionsim serve`` owns its
    process; the embedded service (a test session's process) unfreezes when it stops."""
    gc.collect()
    gc.freeze()


__all__ = ["freeze_startup_heap", "loop_factory", "run_service", "uvicorn_config"]
