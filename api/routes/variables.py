"""``/controllers/{id}/variables/{name}``: read and write variables by controller name;
``PUT /controllers/{id}/variables`` writes a map of them at once, all or nothing.

PMAC ``I16``, ``P5``, ``Q1``, ``M1``; Trio ``VR(5)`` (URL-encoded). The kind decides which
names exist (404 ``not_found`` otherwise) and which values it takes (422 ``validation_error``).
A write acts at the current simulated instant, as an on-line command would.
"""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Path

from ...sim.errors import InvalidValue, NotFound
from ..decoded_json import DecodedJsonRoute
from ..deps import HandleDep
from ..schemas.variables import VariableIn, VariableOut, VariablesIn, VariablesOut

router = APIRouter(tags=["variables"], route_class=DecodedJsonRoute)

NameParam = Annotated[str, Path(min_length=1, max_length=64, description="e.g. I16, P5, VR(5)")]


@router.get("/controllers/{controller_id}/variables/{name}", response_model=VariableOut)
async def get_variable(handle: HandleDep, name: NameParam) -> dict:
    value = handle.apply(handle.controller.get_variable, name)
    return {"name": name.upper(), "value": value}


@router.put("/controllers/{controller_id}/variables/{name}", response_model=VariableOut)
async def put_variable(handle: HandleDep, name: NameParam, body: VariableIn) -> dict:
    handle.apply(handle.controller.set_variable, name, body.value)
    value = handle.controller.get_variable(name)
    return {"name": name.upper(), "value": value}


def _write_all(controller: object, values: dict[str, float]) -> dict[str, float]:
    """Check every name first (a name the kind does not have → 422 naming it, nothing written),
    then write them in the order given, at one simulated instant."""
    for name in values:
        try:
            controller.get_variable(name)  # type: ignore[attr-defined]
        except NotFound:
            raise InvalidValue(f"no such variable {name!r}; nothing was written",
                               field=name) from None
    for name, value in values.items():
        controller.set_variable(name, value)  # type: ignore[attr-defined]
    return {name.upper(): controller.get_variable(name)  # type: ignore[attr-defined]
            for name in values}


@router.put("/controllers/{controller_id}/variables", response_model=VariablesOut)
async def put_variables(handle: HandleDep, body: VariablesIn) -> dict:
    """Write several variables in one request, e.g. ``{"I16": 5, "I17": 10, "P1": 2.5}``.

    Atomic: every name is checked before anything is written; one the controller does not
    have is a 422 ``validation_error`` whose ``field`` names it, and nothing changes.
    """
    return {"values": handle.apply(_write_all, handle.controller, body.root)}
