"""``/controllers/{id}/axes/{axis}``: Trio axes, their move buffers, and moves issued to them.

A move acts at the current simulated instant and never moves the clock, except with
``?wait=true``: then the request waits like a BASIC process at its move line — a virtual clock
is run forward until the move is buffered (at most ``timeout_s`` simulated seconds), a
realtime clock is awaited (at most ``timeout_s`` scaled by the factor, capped at 30 s wall).
A move still not buffered then is withdrawn (nothing queued) and answered 409 ``buffer_full``.
"""

from __future__ import annotations

import asyncio
import contextlib
from typing import Annotated, Any

from fastapi import APIRouter, Path, Query

from ...app.clock import RealtimeClock
from ...app.registry import RUN_UNTIL_WALL_CAP_S, ControllerHandle
from ...sim.errors import BufferFull, NotFound
from ..decoded_json import DecodedJsonRoute
from ..deps import HandleDep
from ..schemas.axes import AxisOut, AxisPatch, MoveIn, MovePlaced

router = APIRouter(tags=["trio axes"], route_class=DecodedJsonRoute)

AxisParam = Annotated[int, Path(ge=0, description="axis number, from 0 (404 beyond the "
                                                  "controller's axes)",
                                json_schema_extra={"maximum": 63})]


def trio_of(handle: ControllerHandle) -> Any:
    """The Trio controller behind ``handle`` (404 for a kind without Trio axes)."""
    ctrl = handle.controller
    if not hasattr(ctrl, "run_program") or not hasattr(ctrl, "axis"):
        raise NotFound(f"controller {handle.id!r} (kind {handle.kind}) has no Trio axes")
    return ctrl


@router.get("/controllers/{controller_id}/axes/{axis}", response_model=AxisOut)
def get_axis(handle: HandleDep, axis: AxisParam) -> dict:
    return handle.apply(trio_of(handle).axis, axis)


@router.patch("/controllers/{controller_id}/axes/{axis}", response_model=AxisOut)
def patch_axis(handle: HandleDep, axis: AxisParam, body: AxisPatch) -> dict:
    params = body.model_dump(exclude_none=True)
    return handle.apply(trio_of(handle).set_axis, axis, **params)


@router.post(
    "/controllers/{controller_id}/axes/{axis}/moves",
    response_model=MovePlaced,
    status_code=201,
)
async def post_move(
    handle: HandleDep,
    axis: AxisParam,
    body: MoveIn,
    wait: Annotated[bool, Query(description="wait (in simulated time) until buffered")] = False,
    timeout_s: Annotated[float, Query(gt=0, le=3600, description="simulated seconds")] = 60.0,
) -> dict:
    ctrl = trio_of(handle)
    if not wait:
        return {"placed": handle.apply(ctrl.move, axis, body.type, body.args, body.process)}
    reply = handle.apply(ctrl.move, axis, body.type, body.args, body.process, True)
    clock = handle.clock
    if not reply.done and not clock.paused:
        if not isinstance(clock, RealtimeClock):
            await handle.run_until_reply(reply, timeout_s)
        else:
            done = asyncio.get_running_loop().create_future()
            reply.add_done_callback(lambda _r: done.done() or done.set_result(None))
            with contextlib.suppress(TimeoutError):
                cap = min(RUN_UNTIL_WALL_CAP_S, timeout_s / clock.factor)
                await asyncio.wait_for(done, timeout=cap)
    if not reply.done:
        handle.apply(ctrl.withdraw_move, reply)
        raise BufferFull(
            f"the move was not buffered within {timeout_s:g} s; nothing was queued",
            process=body.process or 0,
        )
    return {"placed": reply.reply}
