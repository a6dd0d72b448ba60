"""Errors on the wire: one table from the core's stable ``code`` to an HTTP status.

Routes raise :class:`motionsim.sim.errors.MotionSimError` subclasses (never ``HTTPException``); the
handlers here turn them into ``{"code", "message", ...details}`` bodies. Request validation
failures (malformed JSON, a missing or ill-typed field) become 422 ``validation_error`` bodies
that name the field (``"field": "seconds"``) and carry pydantic's ``errors`` list.
"""

from __future__ import annotations

import logging
from typing import Any

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from starlette.exceptions import HTTPException as StarletteHTTPException
from starlette.routing import Match

from ..app.fatal import exit_if_fatal
from ..sim.errors import MotionSimError
from ..sim.pmac import meaning

log = logging.getLogger("motionsim.api")

#: code -> HTTP status. The one place this mapping lives.
STATUS_BY_CODE: dict[str, int] = {
    "not_found": 404,
    "buffer_full": 409,
    "conflict": 409,
    "controller_deleted": 410,
    "not_simulated": 501,
    "watchdog": 409,
    "parse_error": 422,
    "validation_error": 422,
    "client_closed_request": 499,  # nginx's: the client went away (nobody reads the answer)
}

#: Status for a MotionSimError whose code is not in the table.
DEFAULT_STATUS = 400

_HTTP_CODES = {404: "not_found", 405: "method_not_allowed", 413: "body_too_large",
               415: "unsupported_media_type"}


def status_for(code: str) -> int:
    return STATUS_BY_CODE.get(code, DEFAULT_STATUS)


def _loc_to_field(loc: tuple[Any, ...] | list[Any]) -> str:
    """``("body", "clock", "factor")`` -> ``"clock.factor"``; query/path keep their name."""
    parts = [str(p) for p in loc]
    if parts and parts[0] in ("body", "query", "path", "header", "cookie"):
        parts = parts[1:]
    return ".".join(parts) or "body"


def validation_body(exc: RequestValidationError) -> dict[str, Any]:
    """A 422 body naming the first offending field, with every error listed."""
    errors = []
    for err in exc.errors():
        loc = tuple(err.get("loc", ()))
        item = {"field": _loc_to_field(loc), "loc": list(loc), "message": err.get("msg", ""),
                "type": err.get("type", "")}
        errors.append(item)
    if not errors:
        return {"code": "validation_error", "message": "invalid request", "errors": []}
    first = exc.errors()[0]
    if first.get("type") == "json_invalid":
        ctx = first.get("ctx") or {}
        detail = ctx.get("error", "")
        message = f"malformed JSON body{': ' + detail if detail else ''}"
        field = "body"
    else:
        field = errors[0]["field"]
        where = errors[0]["loc"][0] if errors[0]["loc"] else "body"
        if field == "body":
            message = f"request body: {errors[0]['message']}"
        else:
            message = f"{where} field {field!r}: {errors[0]['message']}"
    return {"code": "validation_error", "message": message, "field": field, "errors": errors}


async def _motionsim_error(_: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, MotionSimError)
    body = exc.to_dict()
    if exc.pmac_error is not None and meaning(exc.pmac_error) is not None:
        body["pmac_meaning"] = meaning(exc.pmac_error)  # the Turbo SRM's table
    return JSONResponse(body, status_code=status_for(exc.code))


async def _validation_error(_: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, RequestValidationError)
    return JSONResponse(validation_body(exc), status_code=422)


async def _http_error(request: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, StarletteHTTPException)
    code = _HTTP_CODES.get(exc.status_code, "http_error")
    message = exc.detail if isinstance(exc.detail, str) else str(exc.detail)
    headers = dict(getattr(exc, "headers", None) or {})
    if exc.status_code == 405:
        allowed = allowed_methods(request)
        headers["Allow"] = ", ".join(allowed)
        message = f"{request.method} is not allowed here; allowed: {', '.join(allowed)}"
    return JSONResponse({"code": code, "message": message}, status_code=exc.status_code,
                        headers=headers or None)


def allowed_methods(request: Request) -> list[str]:
    """Every method some route serves at this request's path (the router reports only the
    first route's, and GET and DELETE of one resource are two routes)."""
    methods = []
    for method in _METHODS:
        scope = {**request.scope, "method": method}
        if any(route.matches(scope)[0] is Match.FULL for route in request.app.routes):
            methods.append(method)
    return methods


_METHODS = ("GET", "HEAD", "POST", "PUT", "PATCH", "DELETE")


async def _internal_error(_: Request, exc: Exception) -> JSONResponse:
    exit_if_fatal(exc)  # a MemoryError ends the process (motionsim.app.fatal)
    log.error("internal error", exc_info=exc)
    return JSONResponse({"code": "internal_error",
                         "message": f"internal error: {type(exc).__name__}: {exc}"},
                        status_code=500)


def install_error_handlers(app: FastAPI) -> None:
    """Register the handlers on ``app``."""
    app.add_exception_handler(Exception, _internal_error)
    app.add_exception_handler(MotionSimError, _motionsim_error)
    app.add_exception_handler(RequestValidationError, _validation_error)
    app.add_exception_handler(StarletteHTTPException, _http_error)


__all__ = ["DEFAULT_STATUS", "STATUS_BY_CODE", "install_error_handlers", "status_for",
           "validation_body"]
