"""``/controllers/{id}/events``: the event log, paged over REST or streamed over WebSocket.

The WebSocket (same path; not in ``/openapi.json``) sends first every held event after
``since``, then live events, one JSON event per text message. Each subscriber is an
:class:`motionsim.app.bus.Cursor` on the controller's log: no per-subscriber queue, so a slow
subscriber only falls behind in the ring, never blocks the simulation or the other subscribers, and
when the ring has moved past it, it receives ``{"type": "gap", "from": SEQ, "to": SEQ}`` and
continues.
"""

from __future__ import annotations

import asyncio
import json
from typing import Annotated

from fastapi import APIRouter, Query, WebSocket, WebSocketDisconnect
from motionsim.api.deps import HandleDep
from motionsim.api.schemas.events import EventsPage
from motionsim.app.bus import Cursor
from motionsim.sim.errors import NotFound

router = APIRouter(tags=["events"])

#: Events read from the ring per batch before yielding to the event loop.
WS_BATCH = 256

#: Close codes: unknown controller; bad query; the controller was deleted.
CLOSE_NOT_FOUND = 4404
CLOSE_BAD_QUERY = 4422
CLOSE_DELETED = 4410


@router.get("/controllers/{controller_id}/events", response_model=EventsPage,
            response_model_exclude_unset=True)
async def get_events(
    handle: HandleDep,
    since: Annotated[int, Query(ge=0, description="return events with seq > since")] = 0,
    type: Annotated[list[str] | None, Query(description="only these types (repeatable)")] = None,
    limit: Annotated[int, Query(ge=1, le=100_000)] = 1000,
) -> dict:
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
    batch: bool = False,
) -> None:
    """``batch=true`` (an extension): each message is a JSON array of the events (and gaps)
    read together, up to 256 — for high event rates, where messages per second, not bytes,
    are the limit."""
    try:
        handle = websocket.app.state.registry.get(controller_id)
    except NotFound as exc:
        await websocket.close(code=CLOSE_NOT_FOUND, reason=exc.message[:120])
        return
    if since < 0:
        await websocket.close(code=CLOSE_BAD_QUERY, reason="since must be >= 0")
        return
    await websocket.accept()
    handle.ensure_running()
    cursor = Cursor(handle.controller.log, since, type, handle.id, WS_BATCH)
    loop = asyncio.get_running_loop()
    disconnected = loop.create_task(_until_disconnect(websocket))
    deleted: asyncio.Future[None] = loop.create_future()
    cancel = handle.on_close(lambda: deleted.done() or deleted.set_result(None))
    try:
        while not disconnected.done():
            messages = cursor.read()
            if batch:
                if messages:
                    await websocket.send_text(json.dumps(messages))
            else:
                for message in messages:
                    await websocket.send_text(json.dumps(message))
            if deleted.done():
                await websocket.close(code=CLOSE_DELETED, reason="controller deleted")
                break
            if cursor.behind:
                await asyncio.sleep(0)  # more held: let others run, then continue
            else:
                await cursor.wait(disconnected, deleted)
    except (WebSocketDisconnect, RuntimeError, ConnectionError):
        pass
    finally:
        cancel()
        disconnected.cancel()


async def _until_disconnect(websocket: WebSocket) -> None:
    """Read (and ignore) client messages until the client goes away."""
    while True:
        message = await websocket.receive()
        if message["type"] == "websocket.disconnect":
            return
