"""JSON request bodies decoded once, beside the event loop when they are large.

The body guard (:mod:`motionsim.api.body_guard`) already decodes every JSON body to check it
(UTF-8, depth, finite numbers) — in the worker thread when it is large. FastAPI would decode
it again, on the event loop, before validating it against the route's model: 10 ms per
megabyte, 70 ms for a body at the 8-MiB limit. The guard leaves what it decoded in the
request's scope, and every route reads its JSON from there (:class:`DecodedJsonRoute`, the
``route_class`` of every router): the same value, validated by the same model, with the
same 422 bodies — a malformed body's ``JSONDecodeError`` is the one FastAPI would have met.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Coroutine
from typing import Any

from fastapi import Request, Response
from fastapi.routing import APIRoute

#: Scope key of the decoded body (or its ``json.JSONDecodeError``), set by the body guard.
SCOPE_KEY = "motionsim.decoded_json"


class DecodedRequest(Request):
    """A request whose ``json()`` is the body the guard decoded (decoded here otherwise)."""

    async def json(self) -> Any:
        if not hasattr(self, "_json"):
            if SCOPE_KEY not in self.scope:
                return await super().json()
            decoded = self.scope.pop(SCOPE_KEY)
            if isinstance(decoded, json.JSONDecodeError):
                raise decoded
            self._json = decoded
        return self._json


class DecodedJsonRoute(APIRoute):
    """A route reading JSON bodies through :class:`DecodedRequest`."""

    def get_route_handler(self) -> Callable[[Request], Coroutine[Any, Any, Response]]:
        handler = super().get_route_handler()

        async def decoded(request: Request) -> Response:
            return await handler(DecodedRequest(request.scope, request.receive))

        return decoded


__all__ = ["SCOPE_KEY", "DecodedJsonRoute", "DecodedRequest"]
