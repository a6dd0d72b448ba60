"""``/controllers/{id}/clock``: read and steer a controller's simulated time.

Calls that move time (``advance``, ``run-until``) run the simulation in slices that give the
event loop a turn, so other clients are served meanwhile, and they stop at a slice boundary
when their client disconnects.
"""

from __future__ import annotations

import asyncio
from collections.abc import Awaitable
from typing import Annotated, TypeVar

from fastapi import APIRouter, Path, Request

from ...app.host_paced import HostPacedClock
from ...app.registry import ControllerHandle
from ...sim.errors import Conflict, MotionSimError
from ...sim.events import Event
from ..decoded_json import DecodedJsonRoute
from ..deps import HandleDep
from ..schemas.clock import AdvanceIn, ClockOut, ClockPatch, RunUntilIn, RunUntilOut

router = APIRouter(tags=["clock"], route_class=DecodedJsonRoute)

T = TypeVar("T")

Holder = Annotated[str, Path(pattern=r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,63}$",
                             description="the holder's name (the client chooses it)")]


class ClientGone(MotionSimError):
    """The client disconnected while its call moved time: the work stopped at a slice boundary
    and the request ends as an ordinary answer nobody reads (499), never as an exception
    through the ASGI server (which would log a traceback)."""

    code = "client_closed_request"


async def until_disconnect(request: Request, work: Awaitable[T]) -> T:
    """Await ``work``; cancel it if the client disconnects first (its body is already read, so
    the next ASGI message can only be ``http.disconnect``).

    Raises:
        ClientGone: the client went away (the route's own cancellation propagates as is).
    """
    task = asyncio.ensure_future(work)
    gone = False

    async def watch() -> None:
        nonlocal gone
        while True:
            message = await request.receive()
            if message["type"] == "http.disconnect":
                gone = True
                task.cancel()
                return

    watcher = asyncio.ensure_future(watch())
    try:
        return await task
    except asyncio.CancelledError:
        current = asyncio.current_task()
        if gone and (current is None or not current.cancelling()):
            raise ClientGone("the client disconnected; the call was stopped") from None
        raise
    finally:
        watcher.cancel()


@router.get("/controllers/{controller_id}/clock", response_model=ClockOut)
async def get_clock(handle: HandleDep) -> dict:
    return handle.clock.to_dict()


@router.patch("/controllers/{controller_id}/clock", response_model=ClockOut)
async def patch_clock(body: ClockPatch, handle: HandleDep) -> dict:
    await handle.set_clock(body.mode, factor=body.factor, paused=body.paused,
                           reaction_s=body.reaction_s, holders=body.holders)
    return handle.clock.to_dict()


@router.post("/controllers/{controller_id}/clock/advance", response_model=ClockOut)
async def advance(body: AdvanceIn, handle: HandleDep, request: Request) -> dict:
    """Run a virtual clock forward (409 ``conflict`` on a realtime clock); on a host-paced
    clock the ``holder`` waits that long while the other holders act."""
    await until_disconnect(request, handle.advance(body.seconds, body.holder))
    return handle.clock.to_dict()


@router.post("/controllers/{controller_id}/clock/run-until", response_model=RunUntilOut)
async def run_until(body: RunUntilIn, handle: HandleDep, request: Request) -> dict:
    """Wait for the first *new* event matching ``event``.

    Virtual: runs the simulation until it is emitted (the clock stops at its instant) or
    ``timeout_s`` simulated seconds pass. Host-paced: the ``holder`` waits for it and acts
    ``reaction_s`` after it. Realtime: waits for it, at most ``timeout_s`` of simulated time.
    At most 30 s of wall time in every mode.
    """
    matched, outcome = await until_disconnect(
        request, handle.run_until_outcome(body.event.as_pattern(), body.timeout_s, body.holder))
    return {"matched": _wire(matched, handle.id), "clock": handle.clock.to_dict(),
            "outcome": outcome}


@router.put("/controllers/{controller_id}/clock/holders/{holder}", response_model=ClockOut)
async def put_holder(handle: HandleDep, holder: Holder) -> dict:
    """Register a holder of a host-paced clock, acting now: time waits for its first call."""
    _host_paced(handle).hold(holder)
    return handle.clock.to_dict()


@router.delete("/controllers/{controller_id}/clock/holders/{holder}", response_model=ClockOut)
async def delete_holder(handle: HandleDep, holder: Holder) -> dict:
    """Release a holder: time no longer waits for it; a call it waits in returns
    ``released``. Releasing an unknown holder changes nothing."""
    _host_paced(handle).release(holder)
    return handle.clock.to_dict()


def _host_paced(handle: ControllerHandle) -> HostPacedClock:
    clock = handle.clock
    if not isinstance(clock, HostPacedClock):
        raise Conflict(f"holders belong to a host-paced clock; this one is {clock.mode}")
    return clock


def _wire(event: Event | None, controller: str) -> dict | None:
    return None if event is None else event.to_dict(controller)
