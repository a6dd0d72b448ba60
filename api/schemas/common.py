"""Models shared by every resource: the error body, health."""

from __future__ import annotations

from typing import Annotated, Any

from annotated_types import Ge, Le
from pydantic import BaseModel, BeforeValidator, ConfigDict, Field


def _integral(value: Any) -> Any:
    """``2.0`` -> ``2`` (JSON Schema counts it an integer); ``true``, ``"2"``, ``2.5`` stay
    wrong for a strict ``int``."""
    if isinstance(value, float) and value.is_integer():
        return int(value)
    return value


#: An ``int`` body field in a strict model: integral numbers only, never a bool or a string.
Int = Annotated[int, BeforeValidator(_integral)]


def int_in(low: int, high: int | None = None) -> Any:
    """:data:`Int` within ``low..high``, published in the schema as ``minimum`` / ``maximum``
    (bounds given after the validator would reach ``/openapi.json`` as unknown keywords)."""
    bounds: list[Any] = [Ge(low)] + ([Le(high)] if high is not None else [])
    return Annotated[int, *bounds, BeforeValidator(_integral)]


class ErrorBody(BaseModel):
    """Every error: a stable snake_case ``code``, a message for a person, and details.

    Details by case: ``pmac_error`` (the controller's own ``ERRnnn``), ``field`` (validation),
    ``index`` / ``line`` / ``column`` / ``text`` (parse errors), ``errors`` (every validation
    problem found).
    """

    model_config = ConfigDict(extra="allow", json_schema_extra={
        "examples": [{"code": "not_found", "message": "no controller 'x'; running: pmac, trio"}]})

    code: str = Field(description="stable, snake_case: not_found, buffer_full, conflict, "
                                  "parse_error, validation_error, watchdog")
    message: str
    pmac_error: str | None = Field(None, description="the controller's answer, e.g. ERR006")


class Health(BaseModel):
    """``ok`` once every listener accepts connections."""

    status: str = Field(description="ok | starting")


class ServiceInfo(BaseModel):
    """The service's name, version, where its documentation is, and its controllers."""

    service: str
    version: str
    docs: str = Field(description="Swagger UI, served offline")
    redoc: str = Field("/redoc", description="ReDoc, served offline")
    openapi: str
    dashboard: str = Field("/dashboard", description="the live page of the controllers")
    controllers: list[str]


#: ``responses=`` for the app: the error body for the statuses every route may answer.
ERROR_RESPONSES: dict[int | str, dict] = {
    404: {"model": ErrorBody, "description": "unknown controller or resource (`not_found`)"},
    409: {"model": ErrorBody,
          "description": "state forbids it (`conflict`, `buffer_full`, `watchdog`)"},
    422: {"model": ErrorBody,
          "description": "bad field or program text (`validation_error`, `parse_error`)"},
}

__all__ = ["ERROR_RESPONSES", "ErrorBody", "Health", "Int", "ServiceInfo", "int_in"]
