"""The ``uvicorn.Config`` both ``motionsim serve`` and the embedded service run HTTP with."""

from __future__ import annotations

import gc
from typing import Any

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


__all__ = ["freeze_startup_heap", "uvicorn_config"]
