"""Request bodies checked before any route sees them: size, media type, UTF-8, finite JSON.

An ASGI middleware (no per-request task, no buffering beyond the limit):

* a body longer than ``max_body_bytes`` (``Content-Length`` or counted while it streams) is
  413 ``body_too_large`` — the service never holds more than the limit for one request. The
  rest of the body is read and thrown away first (at most ``DRAIN_BYTES``, for at most
  ``DRAIN_S``): a client that sends its whole body before reading (``requests``,
  ``http.client``) then reads the 413 instead of a connection reset;
* a ``POST`` / ``PATCH`` with a body, or with any ``Content-Type``, must say
  ``application/json`` (415 ``unsupported_media_type``, the message says so): an HTML form
  cannot post JSON across sites, so no state changes from a form (CSRF). ``PUT`` of a Trio
  program takes ``text/plain`` (a ``PUT`` always needs a CORS preflight, which is refused);
* a JSON body must be UTF-8 (422 ``validation_error`` naming the byte offset), nest at most
  ``MAX_DEPTH`` arrays / objects deep, and hold only finite numbers: ``NaN``, ``Infinity``
  and numbers too large for a double (``1e999``) are 422, wherever they are in the body.

The body is then handed on unchanged, with what it decodes to (decoded once, in the worker
thread when large: the routes read it, :mod:`motionsim.api.decoded_json`); FastAPI validates
that against the route's model.
"""

from __future__ import annotations

import asyncio
import json
import math
from collections.abc import Awaitable, Callable, MutableMapping
from typing import Any

import anyio
import anyio.to_thread
from starlette.routing import Match

from ..app.settings import DEFAULT_MAX_BODY_BYTES
from .decoded_json import SCOPE_KEY as DECODED_JSON
from .off_loop import WORKER, without_gc

Scope = MutableMapping[str, Any]
Message = MutableMapping[str, Any]
Receive = Callable[[], Awaitable[Message]]
Send = Callable[[Message], Awaitable[None]]
ASGIApp = Callable[[Scope, Receive, Send], Awaitable[None]]

#: Most bytes of an over-limit body read and discarded before its 413 (beyond: 413, then close).
DRAIN_BYTES = 64 * 1024 * 1024
#: Most wall seconds spent discarding an over-limit body before its 413.
DRAIN_S = 10.0

#: Bodies up to this size are checked on the event loop (a few ms at most); larger ones in
#: one worker thread shared by all requests, so the loop keeps serving everyone meanwhile.
INLINE_CHECK_BYTES = 64 * 1024

#: Deepest nesting of arrays and objects accepted in a JSON body (no request needs more than 4).
MAX_DEPTH = 32

_JSON_METHODS = frozenset({"POST", "PATCH"})
_BODY_METHODS = frozenset({"POST", "PUT", "PATCH", "DELETE"})


class BodyRejected(Exception):
    """A body refused before routing: HTTP ``status`` and the error body."""

    def __init__(self, status: int, code: str, message: str, **details: Any) -> None:
        super().__init__(message)
        self.status = status
        self.body = {"code": code, "message": message, **details}


def header(scope: Scope, name: bytes) -> str | None:
    """The first value of header ``name`` (lower case) in ``scope``."""
    for key, value in scope.get("headers", ()):
        if key == name:
            return value.decode("latin-1")
    return None


def media_type(content_type: str | None) -> str | None:
    """``"application/json; charset=utf-8"`` -> ``"application/json"``."""
    if content_type is None:
        return None
    return content_type.split(";", 1)[0].strip().lower()


def is_json(media: str | None) -> bool:
    return media == "application/json" or (media is not None and media.endswith("+json"))


def check_json(body: bytes) -> Any:
    """Refuse (:class:`BodyRejected`, 422) a body that is not finite, shallow, UTF-8 JSON;
    otherwise what it decodes to (what ``json.loads`` gives), or the ``JSONDecodeError`` of
    a malformed body (FastAPI's 422 reports it: ``UNDECODED`` for a body it decodes
    differently, one starting with a byte-order mark)."""
    try:
        text = body.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise BodyRejected(422, "validation_error",
                           f"request body is not valid UTF-8 (byte {exc.start})",
                           field="body", position=exc.start) from None

    try:
        data = json.loads(text, parse_constant=_NonFinite, parse_float=_finite_or_marker)
    except RecursionError:
        raise BodyRejected(422, "validation_error",
                           f"JSON nested deeper than {MAX_DEPTH} levels", field="body") from None
    except json.JSONDecodeError as exc:
        # malformed JSON: FastAPI answers its 422 (line and column) as before
        return UNDECODED if text.startswith("\ufeff") else exc
    except ValueError as exc:  # e.g. an integer of more than 4300 digits
        raise BodyRejected(422, "validation_error", f"request body: {exc}",
                           field="body") from None
    depth, bad = _scan(data)
    if depth > MAX_DEPTH:
        raise BodyRejected(422, "validation_error",
                           f"JSON nested deeper than {MAX_DEPTH} levels", field="body")
    if bad is not None:
        path, marker = bad
        field = ".".join(str(p) for p in path) or "body"
        raise BodyRejected(422, "validation_error",
                           f"body field {field!r}: {marker.literal[:40]} is not a finite number "
                           "(NaN and Infinity are not allowed)", field=field)
    return data


#: :func:`check_json`'s answer for a body left to FastAPI to decode.
UNDECODED = object()


class _NonFinite:
    """Stands for ``NaN`` / ``Infinity`` / an overflowing number while the body is scanned."""

    __slots__ = ("literal",)

    def __init__(self, literal: str) -> None:
        self.literal = literal


def _finite_or_marker(literal: str) -> float | _NonFinite:
    value = float(literal)
    return value if math.isfinite(value) else _NonFinite(literal)


def _scan(data: Any) -> tuple[int, tuple[tuple[Any, ...], _NonFinite] | None]:
    """Nesting depth of arrays / objects and the first non-finite number with its path
    (iterative: no recursion limit; stops once too deep)."""
    deepest = 0
    bad: tuple[tuple[Any, ...], _NonFinite] | None = None
    stack: list[tuple[Any, tuple[Any, ...]]] = [(data, ())]
    while stack:
        item, path = stack.pop()
        if isinstance(item, _NonFinite):
            if bad is None or len(path) < len(bad[0]):
                bad = (path, item)
            continue
        if isinstance(item, dict):
            children = item.items()
        elif isinstance(item, list):
            children = enumerate(item)
        else:
            continue
        deepest = max(deepest, len(path) + 1)
        if deepest > MAX_DEPTH:
            return deepest, bad
        for key, child in children:  # (a scalar neither nests nor is non-finite: not stacked)
            if isinstance(child, _CONTAINERS):
                stack.append((child, (*path, key)))
    return deepest, bad


#: What :func:`_scan` looks into: nesting and the non-finite number markers.
_CONTAINERS = (dict, list, _NonFinite)


class BodyGuard:
    """The middleware; ``max_body_bytes`` is the 413 limit."""

    def __init__(self, app: ASGIApp, max_body_bytes: int = DEFAULT_MAX_BODY_BYTES,
                 routes: Any = ()) -> None:
        self.app = app
        self.max_body_bytes = max_body_bytes
        #: the app's routes: the media type is checked only where a route serves the method
        #: (elsewhere the router answers 405 / 404 as before)
        self.routes = routes

    def _routed(self, scope: Scope) -> bool:
        return not self.routes or any(r.matches(scope)[0] is Match.FULL for r in self.routes)

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http" or scope["method"] not in _BODY_METHODS:
            await self.app(scope, receive, send)
            return
        try:
            body = await self._read(scope, receive)
        except BodyRejected as exc:
            await _reply(send, exc)
            return
        replayed = False

        async def replay() -> Message:
            nonlocal replayed
            if not replayed:
                replayed = True
                return {"type": "http.request", "body": body, "more_body": False}
            return await receive()

        await self.app(scope, replay, send)

    async def _read(self, scope: Scope, receive: Receive) -> bytes:
        """The whole body (at most the limit), its media type and JSON checked."""
        method = scope["method"]
        limit = self.max_body_bytes
        length = header(scope, b"content-length")
        if length is not None and length.strip().isdigit() and int(length) > limit:
            if (header(scope, b"expect") or "").lower() != "100-continue":
                await _discard(receive)  # (a client waiting for 100 Continue sent nothing)
            raise BodyRejected(413, "body_too_large",
                               f"request body of {int(length)} bytes is over the limit of "
                               f"{limit} bytes (setting max_body_bytes)", limit=limit)
        chunks: list[bytes] = []
        size = 0
        while True:
            message = await receive()
            if message["type"] == "http.disconnect":
                raise BodyRejected(400, "client_disconnected", "client went away")
            chunk = message.get("body", b"")
            size += len(chunk)
            if size > limit:
                if message.get("more_body", False):
                    await _discard(receive)
                raise BodyRejected(413, "body_too_large",
                                   f"request body is over the limit of {limit} bytes "
                                   "(setting max_body_bytes)", limit=limit)
            chunks.append(chunk)
            if not message.get("more_body", False):
                break
        body = b"".join(chunks)
        media = media_type(header(scope, b"content-type"))
        if (method in _JSON_METHODS and (body or media is not None) and not is_json(media)
                and self._routed(scope)):
            got = "no Content-Type" if media is None else f"Content-Type {media!r}"
            raise BodyRejected(415, "unsupported_media_type",
                               f"{method} bodies must be JSON: send 'Content-Type: "
                               f"application/json' (got {got})")
        if body and is_json(media):
            if len(body) <= INLINE_CHECK_BYTES:
                decoded = check_json(body)
            else:  # a large body's scan would hold the loop: one worker thread at a time
                decoded = await anyio.to_thread.run_sync(without_gc, check_json, body,
                                                         limiter=WORKER)
            if decoded is not UNDECODED:  # the routes read it (api/decoded_json.py)
                scope[DECODED_JSON] = decoded
        return body


async def _discard(receive: Receive) -> None:
    """Read and drop the rest of a refused body (bounded by ``DRAIN_BYTES`` and ``DRAIN_S``),
    so the client, done sending, reads the answer rather than a reset."""
    dropped = 0
    try:
        async with asyncio.timeout(DRAIN_S):
            while dropped <= DRAIN_BYTES:
                message = await receive()
                if message["type"] == "http.disconnect":
                    return
                dropped += len(message.get("body", b""))
                if not message.get("more_body", False):
                    return
    except TimeoutError:
        return


async def _reply(send: Send, exc: BodyRejected) -> None:
    await send_error(send, exc.status, exc.body, close=True)


async def send_error(send: Send, status: int, body: dict[str, Any], *, close: bool = False,
                     headers: list[tuple[bytes, bytes]] | None = None) -> None:
    """Answer an HTTP request with an error body (``close``: and end the connection)."""
    data = json.dumps(body).encode()
    out = [(b"content-type", b"application/json"), (b"content-length", str(len(data)).encode())]
    if close:
        out.append((b"connection", b"close"))
    await send({"type": "http.response.start", "status": status, "headers": out + (headers or [])})
    await send({"type": "http.response.body", "body": data})


__all__ = ["DEFAULT_MAX_BODY_BYTES", "DRAIN_BYTES", "DRAIN_S", "MAX_DEPTH", "BodyGuard",
           "BodyRejected", "check_json", "header", "is_json", "media_type", "send_error"]
