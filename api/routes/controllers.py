"""``/controllers``: list, create, inspect, delete and power-cycle controllers."""

from __future__ import annotations

from fastapi import APIRouter, Response

from ..decoded_json import DecodedJsonRoute
from ..deps import HandleDep, RegistryDep
from ..schemas.controllers import ControllerIn, ControllerOut

router = APIRouter(tags=["controllers"], route_class=DecodedJsonRoute)


@router.get("/controllers", response_model=list[ControllerOut])
async def list_controllers(registry: RegistryDep) -> list[dict]:
    return [h.snapshot() for h in registry]


@router.post("/controllers", status_code=201, response_model=ControllerOut)
async def create_controller(body: ControllerIn, registry: RegistryDep) -> dict:
    """Create a controller of an installed ``kind`` (422 for an unknown kind or config key)."""
    handle = registry.add(body.kind, body.id, clock=body.clock.mode, factor=body.clock.factor,
                          paused=body.clock.paused, config=body.config,
                          reaction_s=body.clock.reaction_s, holders=body.clock.holders)
    return handle.to_dict()


@router.get("/controllers/{controller_id}", response_model=ControllerOut)
async def get_controller(handle: HandleDep) -> dict:
    return handle.snapshot()


@router.delete("/controllers/{controller_id}", status_code=204)
async def delete_controller(handle: HandleDep, registry: RegistryDep) -> Response:
    await registry.remove(handle.id)
    return Response(status_code=204)


@router.post("/controllers/{controller_id}/reset", response_model=ControllerOut)
async def reset_controller(handle: HandleDep) -> dict:
    """The power cycle: factory defaults, buffers and programs gone; time goes on."""
    handle.apply(handle.controller.reset)
    return handle.to_dict()
