"""Limits of the HTTP port itself, below the ASGI app: connections, header time, header size.

uvicorn's own settings are used where it has one (:func:`uvicorn_limits`): ``limit_concurrency``
(503 to a request when that many connections or requests are open) and ``timeout_keep_alive``
(an idle connection between requests is closed). What it lacks is added by
:func:`limited_protocol`, a subclass of its httptools protocol:

* **connection cap** (``http_max_connections``): a connection accepted while that many are
  open (HTTP and WebSocket together) may only ask ``GET /health``: :data:`HEALTH_RESERVE`
  more connections are kept for it, so a container health check is answered whatever the
  clients hold; any other request on such a connection (or one that sends nothing) is
  answered 503 ``too_many_connections`` and closed (a silent one after
  :data:`HEALTH_WAIT_S`), and past the reserve a connection is
  refused at once, so no file descriptor is held for it;
* **WebSocket pool**: at most :func:`websocket_cap` of the connections (3/4 of
  ``http_max_connections``) may be WebSockets; one more upgrade is answered 503
  ``too_many_websockets`` — idle subscribers cannot take the REST clients' share;
* **file descriptors**: a connection whose descriptor is within :data:`FD_MARGIN` of the
  process's limit (``RLIMIT_NOFILE``) is refused at once, so the service refuses before the
  operating system does (no "Too many open files" from ``accept``);
* **header time-out** (``http_header_timeout_s``): a request whose headers are not complete that
  long after the connection opened (or after the previous response) is answered 408
  ``request_timeout`` and closed — half-sent requests cannot pile up;
* **header size** (``http_max_header_bytes``): a request line plus headers larger than that is
  answered 431 ``headers_too_large`` and closed, before the app sees it and before more of it
  is buffered.

Each refusal is a JSON error body naming the limit and its setting.
"""

from __future__ import annotations

import json
import resource
from dataclasses import dataclass
from typing import Any, Final

from uvicorn.protocols.http.httptools_impl import HttpToolsProtocol

#: Connections over ``http_max_connections`` kept for ``GET /health`` only ``[INF]``.
HEALTH_RESERVE: Final = 32
#: Seconds a connection over the cap has to send its ``GET /health`` headers ``[INF]``.
HEALTH_WAIT_S: Final = 0.5
#: File descriptors kept free below the process's limit (files, the TCP protocol ports).
FD_MARGIN: Final = 128


def websocket_cap(max_connections: int) -> int:
    """WebSocket connections allowed at once: 3/4 of the cap (at least 1) ``[INF]``, the
    rest of the pool is kept for REST."""
    return max(1, max_connections * 3 // 4)


def fd_ceiling() -> int:
    """The highest descriptor number a new connection may have (the soft limit less the
    margin)."""
    soft, _hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    if soft == resource.RLIM_INFINITY:
        return 1 << 30
    return max(16, soft - FD_MARGIN)


@dataclass(frozen=True, slots=True)
class HttpLimits:
    """What the HTTP port allows (the settings of the same names)."""

    max_connections: int = 800
    header_timeout_s: float = 10.0
    max_header_bytes: int = 16 * 1024
    keep_alive_s: int = 5


_REASONS = {408: b"Request Timeout", 431: b"Request Header Fields Too Large",
            503: b"Service Unavailable"}


def _error_response(status: int, code: str, message: str, limit: float) -> bytes:
    body = json.dumps({"code": code, "message": message, "limit": limit}).encode()
    head = (b"HTTP/1.1 %d %s\r\ncontent-type: application/json\r\ncontent-length: %d\r\n"
            b"connection: close\r\n\r\n" % (status, _REASONS[status], len(body)))
    return head + body


def limited_protocol(limits: HttpLimits) -> type[HttpToolsProtocol]:
    """uvicorn's httptools protocol with ``limits`` enforced (pass it as ``http=``)."""

    class LimitedHttpProtocol(HttpToolsProtocol):
        _limits = limits

        def connection_made(self, transport: Any) -> None:  # type: ignore[override]
            super().connection_made(transport)
            self._header_timer: Any = None
            self._header_bytes = 0
            self._in_headers = False
            self._refused = False
            self._health_only = False
            cap = self._limits.max_connections
            sock = transport.get_extra_info("socket")
            fd = sock.fileno() if sock is not None else -1
            if fd > _FD_CEILING:
                self._refuse(503, "too_many_connections",
                             f"the process is near its file-descriptor limit "
                             f"({_FD_CEILING + FD_MARGIN}); try again later", cap)
                return
            open_ = len(self.connections)
            if open_ > cap + HEALTH_RESERVE:
                self._too_many()
                return
            self._health_only = open_ > cap  # over the pool: GET /health only
            self._arm_header_timer()

        def _too_many(self) -> None:
            cap = self._limits.max_connections
            self._refuse(503, "too_many_connections",
                         f"{cap} connections are open, the most allowed "
                         f"(setting http_max_connections); try again later", cap)

        # -- the WebSocket pool ----------------------------------------------------------

        def handle_websocket_upgrade(self) -> None:
            cap = websocket_cap(self._limits.max_connections)
            ws = sum(1 for c in self.connections if not isinstance(c, HttpToolsProtocol))
            if ws >= cap or self._health_only:
                self._refuse(503, "too_many_websockets",
                             f"{cap} WebSocket connections are open, the most allowed (3/4 of "
                             "setting http_max_connections); try again later", cap)
                return
            super().handle_websocket_upgrade()

        # -- header time-out -------------------------------------------------------------

        def _arm_header_timer(self) -> None:
            self._cancel_header_timer()
            wait = self._limits.header_timeout_s
            if self._health_only:
                wait = min(wait, HEALTH_WAIT_S)
            self._header_timer = self.loop.call_later(wait, self._header_timeout)

        def _cancel_header_timer(self) -> None:
            if self._header_timer is not None:
                self._header_timer.cancel()
                self._header_timer = None

        def _header_timeout(self) -> None:
            self._header_timer = None
            if self.cycle is not None and not self.cycle.response_complete:
                return  # a request is being served: its headers were complete
            if self._health_only:
                self._too_many()  # over the pool and no GET /health came
                return
            if self._in_headers or self._header_bytes or self.cycle is None:
                limit = self._limits.header_timeout_s
                self._refuse(408, "request_timeout",
                             f"the request headers were not complete within {limit:g} s "
                             "(setting http_header_timeout_s)", limit)

        def on_response_complete(self) -> None:
            super().on_response_complete()
            if not self.transport.is_closing():
                self._arm_header_timer()

        def connection_lost(self, exc: Exception | None) -> None:
            self._cancel_header_timer()
            super().connection_lost(exc)

        # -- header size -----------------------------------------------------------------

        def data_received(self, data: bytes) -> None:
            if self._refused:
                return
            if not self._in_headers and (self.cycle is None or self.cycle.response_complete):
                self._header_bytes = 0  # a new request starts with these bytes
            pending = self._in_headers or self.cycle is None or self.cycle.response_complete
            if pending:
                self._header_bytes += len(data)
            super().data_received(data)
            if (self._in_headers and self._header_bytes > self._limits.max_header_bytes
                    and not self._refused):
                self._too_large()

        def on_message_begin(self) -> None:
            super().on_message_begin()
            self._in_headers = True
            self._exact_header_bytes = 0

        def on_url(self, url: bytes) -> None:
            super().on_url(url)
            self._exact_header_bytes += len(url)

        def on_header(self, name: bytes, value: bytes) -> None:
            super().on_header(name, value)
            self._exact_header_bytes += len(name) + len(value) + 4

        def on_headers_complete(self) -> None:
            self._cancel_header_timer()
            self._in_headers = False
            self._header_bytes = 0
            if self._refused:
                return
            if self._exact_header_bytes > self._limits.max_header_bytes:
                self._too_large()
                return
            if self._health_only and (self.parser.get_method() != b"GET"
                                      or self.url.split(b"?", 1)[0] != b"/health"):
                self._too_many()
                return
            super().on_headers_complete()

        def _too_large(self) -> None:
            limit = self._limits.max_header_bytes
            self._refuse(431, "headers_too_large",
                         f"the request line and headers are over the limit of {limit} bytes "
                         "(setting http_max_header_bytes)", limit)

        # -- refusal ---------------------------------------------------------------------

        def _refuse(self, status: int, code: str, message: str, limit: float) -> None:
            self._refused = True
            self._cancel_header_timer()
            # no longer open from here on: while it closes it must not count towards the
            # cap (uvicorn's ``limit_concurrency`` would answer an admitted client's next
            # request 503 during a flood of refused connections)
            self.connections.discard(self)
            if not self.transport.is_closing():
                self.transport.write(_error_response(status, code, message, limit))
                self.transport.close()

    return LimitedHttpProtocol


#: Read once: the limit does not change while the service runs.
_FD_CEILING = fd_ceiling()


def uvicorn_limits(limits: HttpLimits) -> dict[str, Any]:
    """The ``uvicorn.Config`` keyword arguments that enforce ``limits``."""
    # uvicorn answers 503 from ``limit_concurrency`` open connections (or requests) on; the
    # protocol refuses connections over ``max_connections`` (and its /health reserve) itself
    return {"http": limited_protocol(limits),
            "limit_concurrency": limits.max_connections + HEALTH_RESERVE + 1,
            "timeout_keep_alive": limits.keep_alive_s}


__all__ = ["FD_MARGIN", "HEALTH_RESERVE", "HEALTH_WAIT_S", "HttpLimits", "fd_ceiling",
           "limited_protocol", "uvicorn_limits", "websocket_cap"]
