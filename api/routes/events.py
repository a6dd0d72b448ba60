"""``/controllers/{id}/events``: the event log, paged over REST or streamed over WebSocket.

The WebSocket (same path; not in ``/openapi.json``) sends first every held event after
``since``, then live events, one JSON event per text message. Each subscriber reads the log
by ``seq`` straight from the controller's ring and sleeps on ``log.wake_on_next`` between
batches, so there is no per-subscriber queue at all: a slow subscriber only falls behind in
the ring, never blocks the simulation or the other subscribers, and when the ring has moved
past it, it receives ``{"type": "gap", "from": SEQ, "to": SEQ}`` and continues.
"""

from __future__ import annotations

import asyncio
import json
from typing import Annotated

from fastapi import APIRouter, Query, WebSocket, WebSocketDisconnect

from api.deps import HandleDep
from api.schemas.events import EventsPage
from sim.errors import NotFound

router = APIRouter(tags=["events"])

#: Events read from the ring per batch before yielding to the event loop.
WS_BATCH = 256


@router.get("/controllers/{controller_id}/events", response_model=EventsPage,
            response_model_exclude_unset=True)
def get_events(
    handle: HandleDep,
    since: Annotated[int, Query(ge=0, description="return events with seq > since")] = 0,
    type: Annotated[list[str] | None, Query(description="only these types (repeatable)")] = None,
    limit: Annotated[int, Query(ge=1, le=100_000)] = 1000,
) -> dict:
    handle.ensure_running()
    handle.clock.sync()
    res = handle.controller.log.read(since, type or None, limit)
    cid = handle.id
    out: dict = {"events": [e.to_dict(cid) for e in res.events], "next": res.next}
    if res.gap is not None:
        out["gap"] = res.gap.to_dict()
    return out


@router.websocket("/controllers/{controller_id}/events")
async def stream_events(
    websocket: WebSocket,
    controller_id: str,
    since: int = 0,
    type: Annotated[list[str] | None, Query()] = None,
) -> None:
    try:
        handle = websocket.app.state.registry.get(controller_id)
    except NotFound as exc:
        await websocket.close(code=4404, reason=exc.message[:120])
        return
    if since < 0:
        await websocket.close(code=4422, reason="since must be >= 0")
        return
    await websocket.accept()
    handle.ensure_running()
    log = handle.controller.log
    types = frozenset(type) if type else None
    cid = handle.id
    loop = asyncio.get_running_loop()
    disconnected = loop.create_task(_until_disconnect(websocket))
    try:
        while not disconnected.done():
            res = log.read(since, types, WS_BATCH)
            if res.gap is not None:
                await websocket.send_text(json.dumps(res.gap.to_dict()))
            for event in res.events:
                await websocket.send_text(json.dumps(event.to_dict(cid)))
            since = res.next
            if since < log.last_seq:
                await asyncio.sleep(0)  # more held: let others run, then continue
                continue
            woken: asyncio.Future[None] = loop.create_future()
            log.wake_on_next(lambda f=woken: f.done() or f.set_result(None))
            if log.last_seq > since:  # an event slipped in between read and wake_on_next
                continue
            await asyncio.wait({woken, disconnected}, return_when=asyncio.FIRST_COMPLETED)
    except (WebSocketDisconnect, RuntimeError, ConnectionError):
        pass
    finally:
        disconnected.cancel()


async def _until_disconnect(websocket: WebSocket) -> None:
    """Read (and ignore) client messages until the client goes away."""
    while True:
        message = await websocket.receive()
        if message["type"] == "websocket.disconnect":
            return
