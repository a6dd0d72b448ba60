"""``/controllers/{id}/variables/{name}``: read and write variables by controller name.

PMAC ``I16``, ``P5``, ``Q1``, ``M1``; Trio ``VR(5)`` (URL-encoded). The kind decides which
names exist (404 ``not_found`` otherwise) and which values it takes (422 ``validation_error``).
A write acts at the current simulated instant, as an on-line command would.
"""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Path
from motionsim.api.deps import HandleDep
from motionsim.api.schemas.variables import VariableIn, VariableOut

router = APIRouter(tags=["variables"])

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
