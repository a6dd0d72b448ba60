"""Who may talk to the service from a browser or a network: Host, Origin and an optional token.

An ASGI middleware in front of every HTTP request and WebSocket:

* **Host allow-list** (DNS rebinding): the ``Host`` header must name an allowed host — by
  default the loopback names (``localhost``, ``127.0.0.1``, ``::1``) and the address the
  service is bound to (unless that is a wildcard such as ``0.0.0.0``); more with the setting
  ``allowed_hosts`` (env ``MOTIONSIM_ALLOWED_HOSTS``, comma-separated; ``*`` = any). Otherwise
  400 ``invalid_host`` (a WebSocket is refused at the handshake).
* **Origin** (cross-site requests, cross-site WebSocket hijacking): a request or WebSocket that
  carries an ``Origin`` header must come from the service's own origin — its ``Host``, or an
  allowed host name **on the service's own port** (``http://localhost:8000`` for a service
  reached as ``127.0.0.1:8000``) — or a configured CORS origin; a page of another local app
  (``http://localhost:9999``) is not the service. Otherwise 403 ``forbidden_origin`` (a
  WebSocket: accepted, then closed with 4403 and the reason).
* **Token** (optional, setting ``token`` / ``--token`` / env ``MOTIONSIM_TOKEN``): every request
  except ``GET /health`` must carry it as ``Authorization: Bearer TOKEN``, a ``token=`` query
  parameter (for WebSockets and a first dashboard visit; the answer then sets the cookie) or the
  ``motionsim_token`` cookie; otherwise 401 ``unauthorized`` (a WebSocket: close 4401).

What it does not do: no TLS, no users or roles, and the TCP protocol ports (PMAC Ethernet, Trio
telnet, Modbus) have no authentication at all — as on the real controllers.
"""

from __future__ import annotations

import hmac
from collections.abc import Iterable
from http.cookies import SimpleCookie
from urllib.parse import parse_qs, urlsplit

from .body_guard import ASGIApp, Receive, Scope, Send, header, send_error

#: Always allowed in ``Host``: the loopback names.
LOOPBACK_HOSTS = frozenset({"localhost", "127.0.0.1", "::1"})

#: Bind addresses that mean "every interface": they name no host to allow.
WILDCARD_BINDS = frozenset({"0.0.0.0", "::", ""})

COOKIE = "motionsim_token"

#: Close codes a WebSocket refused here gets (after the handshake, so clients see them).
CLOSE_FORBIDDEN_ORIGIN = 4403
CLOSE_UNAUTHORIZED = 4401

#: Paths open without the token (container health checks).
OPEN_PATHS = frozenset({"/health"})


def host_name(value: str) -> str:
    """``"Example.com:8000"`` -> ``"example.com"``; ``"[::1]:80"`` -> ``"::1"``."""
    value = value.strip().lower()
    if value.startswith("["):
        return value[1:].split("]", 1)[0]
    if value.count(":") == 1:
        return value.split(":", 1)[0]
    return value


def _port(netloc: str, scheme: str) -> int | None:
    """The port of ``host[:port]`` (the scheme's default when none is written)."""
    netloc = netloc.strip().lower()
    tail = netloc.rsplit("]", 1)[1] if netloc.startswith("[") else netloc
    if tail.count(":") == 1:
        try:
            return int(tail.rsplit(":", 1)[1])
        except ValueError:
            return None
    return {"http": 80, "https": 443, "ws": 80, "wss": 443}.get(scheme)


def allowed_host_set(bind_host: str, extra: Iterable[str]) -> frozenset[str]:
    """Loopback names, the bound address (unless a wildcard) and the configured ones."""
    hosts = set(LOOPBACK_HOSTS)
    if bind_host not in WILDCARD_BINDS:
        hosts.add(host_name(bind_host))
    hosts.update(host_name(h) if h != "*" else "*" for h in extra if h.strip())
    return frozenset(hosts)


class WebGuard:
    """The middleware. ``allowed_hosts``: from :func:`allowed_host_set`."""

    def __init__(self, app: ASGIApp, allowed_hosts: frozenset[str], token: str | None = None,
                 cors_origins: Iterable[str] = ()) -> None:
        self.app = app
        self.allowed_hosts = allowed_hosts
        self.any_host = "*" in allowed_hosts
        self.token = token or None
        self.cors_origins = frozenset(o.rstrip("/").lower() for o in cors_origins)

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        kind = scope["type"]
        if kind not in ("http", "websocket"):
            await self.app(scope, receive, send)
            return
        host = header(scope, b"host") or ""
        if not self.any_host and host_name(host) not in self.allowed_hosts:
            message = (f"Host {host!r} is not allowed; allowed: "
                       f"{', '.join(sorted(self.allowed_hosts))} (setting allowed_hosts, env "
                       "MOTIONSIM_ALLOWED_HOSTS)")
            await self._refuse(scope, receive, send, 400, "invalid_host", message, None)
            return
        origin = header(scope, b"origin")
        if origin is not None and not self._origin_ok(origin, host):
            message = (f"Origin {origin!r} may not use this service (not its own origin, an "
                       "allowed host or a configured CORS origin)")
            await self._refuse(scope, receive, send, 403, "forbidden_origin", message,
                               CLOSE_FORBIDDEN_ORIGIN)
            return
        set_cookie = False
        if self.token is not None and scope.get("path") not in OPEN_PATHS:
            ok, from_query = self._token_ok(scope)
            if not ok:
                await self._refuse(scope, receive, send, 401, "unauthorized",
                                   "this service needs its token: 'Authorization: Bearer "
                                   "TOKEN', ?token=TOKEN or the motionsim_token cookie",
                                   CLOSE_UNAUTHORIZED)
                return
            set_cookie = from_query and kind == "http"
        if not set_cookie:
            await self.app(scope, receive, send)
            return
        cookie = f"{COOKIE}={self.token}; Path=/; HttpOnly; SameSite=Strict".encode()

        async def send_with_cookie(message: dict) -> None:
            if message["type"] == "http.response.start":
                message = {**message, "headers": [*message.get("headers", []),
                                                  (b"set-cookie", cookie)]}
            await send(message)

        await self.app(scope, receive, send_with_cookie)

    def _origin_ok(self, origin: str, host: str) -> bool:
        origin = origin.strip().rstrip("/").lower()
        if origin in self.cors_origins or "*" in self.cors_origins:
            return True
        parts = urlsplit(origin)
        if not parts.netloc:
            return False  # "null" (a sandboxed page, a file: URL)
        if parts.netloc == host.strip().lower():
            return True  # same origin: e.g. the dashboard served by this service
        if _port(parts.netloc, parts.scheme) != _port(host, parts.scheme):
            return False  # another app on this machine, whatever its host name
        return self.any_host or host_name(parts.netloc) in self.allowed_hosts

    def _token_ok(self, scope: Scope) -> tuple[bool, bool]:
        """(token valid, it came in the query string)."""
        assert self.token is not None
        want = self.token.encode()
        auth = header(scope, b"authorization")
        if auth is not None and auth[:7].lower() == "bearer ":
            return hmac.compare_digest(auth[7:].strip().encode(), want), False
        query = parse_qs(scope.get("query_string", b"").decode("latin-1"))
        if "token" in query:
            return hmac.compare_digest(query["token"][0].encode(), want), True
        cookies = header(scope, b"cookie")
        if cookies:
            jar: SimpleCookie = SimpleCookie()
            try:
                jar.load(cookies)
            except Exception:  # a malformed Cookie header is no token
                return False, False
            if COOKIE in jar:
                return hmac.compare_digest(jar[COOKIE].value.encode(), want), False
        return False, False

    @staticmethod
    async def _refuse(scope: Scope, receive: Receive, send: Send, status: int, code: str,
                      message: str, close_code: int | None) -> None:
        body = {"code": code, "message": message}
        if scope["type"] == "http":
            headers = [(b"www-authenticate", b"Bearer")] if status == 401 else None
            await send_error(send, status, body, headers=headers)
            return
        await receive()  # websocket.connect
        if close_code is None:
            await send({"type": "websocket.close", "code": 1008, "reason": ""})  # -> HTTP 403
            return
        await send({"type": "websocket.accept"})
        reason = message.encode()[:120].decode(errors="ignore")  # a close reason: 123 bytes
        await send({"type": "websocket.close", "code": close_code, "reason": reason})


__all__ = ["CLOSE_FORBIDDEN_ORIGIN", "CLOSE_UNAUTHORIZED", "COOKIE", "LOOPBACK_HOSTS",
           "WebGuard", "allowed_host_set", "host_name"]
