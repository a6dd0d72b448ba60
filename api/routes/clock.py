"""``/controllers/{id}/clock``: read and steer a controller's simulated time."""

from __future__ import annotations

from fastapi import APIRouter
from motionsim.api.deps import HandleDep
from motionsim.api.schemas.clock import AdvanceIn, ClockOut, ClockPatch, RunUntilIn, RunUntilOut
from motionsim.app.clock import VirtualClock
from motionsim.sim.errors import Conflict
from motionsim.sim.events import Event

router = APIRouter(tags=["clock"])


@router.get("/controllers/{controller_id}/clock", response_model=ClockOut)
async def get_clock(handle: HandleDep) -> dict:
    return handle.clock.to_dict()


@router.patch("/controllers/{controller_id}/clock", response_model=ClockOut)
async def patch_clock(body: ClockPatch, handle: HandleDep) -> dict:
    await handle.set_clock(body.mode, factor=body.factor, paused=body.paused)
    return handle.clock.to_dict()


@router.post("/controllers/{controller_id}/clock/advance", response_model=ClockOut)
async def advance(body: AdvanceIn, handle: HandleDep) -> dict:
    """Run a virtual clock forward (409 ``conflict`` on a realtime clock)."""
    clock = handle.clock
    if not isinstance(clock, VirtualClock):
        raise Conflict("a realtime clock cannot be advanced; PATCH its mode to virtual first")
    clock.advance(body.seconds)
    return clock.to_dict()


@router.post("/controllers/{controller_id}/clock/run-until", response_model=RunUntilOut)
async def run_until(body: RunUntilIn, handle: HandleDep) -> dict:
    """Wait for the first *new* event matching ``event``.

    Virtual: runs the simulation until it is emitted (the clock stops at its instant) or
    ``timeout_s`` simulated seconds pass. Realtime: waits for it, at most ``timeout_s`` of
    simulated time and at most 30 s of wall time.
    """
    matched = await handle.run_until(body.event.as_pattern(), body.timeout_s)
    return {"matched": _wire(matched, handle.id), "clock": handle.clock.to_dict()}


def _wire(event: Event | None, controller: str) -> dict | None:
    return None if event is None else event.to_dict(controller)
