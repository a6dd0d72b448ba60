"""The ``uvicorn.Config`` both ``motionsim serve`` and the embedded service run HTTP with."""

from __future__ import annotations

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


__all__ = ["uvicorn_config"]
