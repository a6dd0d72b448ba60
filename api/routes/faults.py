"""``/controllers/{id}/faults``: seeded fault injection for testing a host's retry logic.

POST adds one fault (:mod:`motionsim.app.faults`: delayed, dropped or reset replies on the TCP
protocols, a forced ``ERRnnn``, a stalled card, a lost BREQ edge); GET lists them with what they
have done; DELETE clears them (all, or one by id). Every injection is a ``fault`` event.
"""

from __future__ import annotations

from fastapi import APIRouter, Path
from fastapi.responses import Response

from ...app.faults import FaultSpec, faults_of
from ..decoded_json import DecodedJsonRoute
from ..deps import HandleDep
from ..schemas.faults import FaultList, FaultOut

router = APIRouter(tags=["faults"], route_class=DecodedJsonRoute)


@router.post("/controllers/{controller_id}/faults", response_model=FaultOut, status_code=201)
async def add_fault(handle: HandleDep, spec: FaultSpec) -> dict:
    """Add a fault, e.g. ``{"kind": "reply_drop", "match": "^PR", "nth": 3}``.

    Refused with 422 naming the field when a value is impossible, or with ``field: kind``
    for a kind the controller does not have; nothing changes then.
    """
    return handle.apply(faults_of(handle.controller).add, spec)


@router.get("/controllers/{controller_id}/faults", response_model=FaultList)
async def list_faults(handle: HandleDep) -> dict:
    return {"faults": handle.apply(faults_of(handle.controller).list)}


@router.delete("/controllers/{controller_id}/faults", status_code=204)
async def clear_faults(handle: HandleDep) -> Response:
    """Remove every fault (a stall under way ends now)."""
    handle.apply(faults_of(handle.controller).clear)
    return Response(status_code=204)


@router.delete("/controllers/{controller_id}/faults/{fault_id}", status_code=204)
async def remove_fault(handle: HandleDep,
                       fault_id: str = Path(max_length=16, description="e.g. `f1`")) -> Response:
    handle.apply(faults_of(handle.controller).remove, fault_id)
    return Response(status_code=204)
