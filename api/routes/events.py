"""``/controllers/{id}/events``: the event log, paged over REST or streamed over WebSocket.

The WebSocket (same path; not in ``/openapi.json``) sends first every held event after
``since``, then live events, one JSON event per text message. Each subscriber is an
:class:`motionsim.app.bus.Cursor` on the controller's log: no per-subscriber queue, so a slow
subscriber only falls behind in the ring, never blocks the simulation or the other subscribers, and
when the ring has moved past it, it receives ``{"type": "gap", "from": SEQ, "to": SEQ}`` and
continues. Its first message is ``{"type": "epoch", ...}`` (the log's incarnation, see
:func:`motionsim.app.bus.epoch_message`). Served by uvicorn, a subscriber that has caught up is
written by its log's fan-out (:mod:`motionsim.api.ws_fanout`: the same messages, framed once
for all).

A WebSocket that cannot be served is accepted and then closed with a code and a reason a real
client sees (a close before the handshake would reach it as a bare HTTP 403): 4404 unknown
controller, 4422 bad query (``since`` not an integer >= 0 — ``abc``, ``1.5`` —, ``batch``
not a boolean, an unknown event type: preceded by one ``{"type": "error", "code":
"validation_error", "message", "field", ...}`` message, since a close reason holds only 123
bytes), 4410 the controller was deleted while streaming. The query is validated by the route
itself after the handshake, never by FastAPI before it (which would refuse with HTTP 403).
"""

from __future__ import annotations

import asyncio
import json
import time
from typing import Annotated

from fastapi import APIRouter, Query, Response, WebSocket, WebSocketDisconnect
from pydantic import Field

from ...app.bus import Cursor, epoch_message
from ...app.clock import SLICE_S, loop_turns
from ...sim.controller import Controller
from ...sim.errors import InvalidValue, NotFound
from ..decoded_json import DecodedJsonRoute
from ..deps import HandleDep
from ..schemas.events import EventsPage, StreamQuery, stream_query
from ..ws_fanout import frames, messages, stream_live
from ..ws_protocol import EXTENSION

router = APIRouter(tags=["events"], route_class=DecodedJsonRoute)

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
    since: Annotated[int, Query(ge=0, le=2**63 - 1,
                                description="return events with seq > since")] = 0,
    type: Annotated[list[Annotated[str, Field(min_length=1, max_length=64)]] | None, Query(
        max_length=64, description="only these types (repeatable; each one the controller "
                                   "emits, 422 otherwise)")] = None,
    limit: Annotated[int, Query(ge=1, le=100_000)] = 1000,
    epoch: Annotated[str | None, Query(
        max_length=64, description="the `epoch` of the page `since` came from; a different "
                                   "one (the log was re-created) answers a `reset`")] = None,
) -> Response:
    handle.clock.sync()
    log = handle.controller.log
    check_types(handle.controller, type)
    since, reset = log.resume(since, epoch)
    res = log.read(since, type or None, limit)
    cid = handle.id
    # A page of up to 100 000 events takes seconds to encode: in slices that give the loop a
    # turn, straight to JSON text (the events are read above, at one instant)
    events: list[str] = []
    end = time.monotonic() + SLICE_S
    for n, event in enumerate(res.events, 1):
        events.append(json.dumps(_wire_form(event.to_dict(cid))))
        if n % 64 == 0 and time.monotonic() > end:
            await loop_turns()
            end = time.monotonic() + SLICE_S
    tail: dict = {"next": res.next}
    if res.gap is not None:
        tail["gap"] = res.gap.to_dict()
    if reset is not None:
        tail["reset"] = reset.to_dict()
    text = (json.dumps({"epoch": log.epoch})[:-1] + ', "events": [' + ", ".join(events)
            + "], " + json.dumps(tail)[1:])
    return Response(text, media_type="application/json")


def _wire_form(event: dict) -> dict:
    """An event as ``EventOut`` gives it: ``seq``, ``t`` (a float), ``type``, ``controller``
    first, then the type's own fields."""
    out = {"seq": event["seq"], "t": float(event["t"]), "type": event["type"],
           "controller": event["controller"]}
    out.update((k, v) for k, v in event.items() if k not in out)
    return out


def check_types(controller: Controller, types: list[str] | None) -> None:
    """Refuse (422 ``validation_error``) event types this controller never emits."""
    unknown = controller.unknown_event_types(types or ())
    if unknown:
        raise InvalidValue(
            f"unknown event type {unknown[0]!r}; valid types: "
            f"{', '.join(controller.known_event_types())}", field="type",
            valid=controller.known_event_types())


@router.websocket("/controllers/{controller_id}/events")
async def stream_events(websocket: WebSocket, controller_id: str) -> None:
    """Query (:class:`motionsim.api.schemas.events.StreamQuery`): ``since``, ``type``
    (repeatable), ``batch=true`` (an extension: each message is a JSON array of the events and
    gaps read together, up to 256 — for high event rates, where messages per second, not bytes,
    are the limit), ``epoch`` (the log epoch ``since`` belongs to; a stale one: ``reset``)."""
    await websocket.accept()
    try:
        handle = websocket.app.state.registry.get(controller_id)
    except NotFound as exc:
        await websocket.close(code=CLOSE_NOT_FOUND, reason=_reason(exc.message))
        return
    try:
        query: StreamQuery = stream_query(websocket.query_params)
        since, type, batch, epoch = query.since, query.type, query.batch, query.epoch
        check_types(handle.controller, type)
    except InvalidValue as exc:
        # the close reason holds only 123 bytes: the whole error (every valid type) goes first
        await websocket.send_text(json.dumps({"type": "error", **exc.to_dict()}))
        await websocket.close(code=CLOSE_BAD_QUERY, reason=_reason(exc.message))
        return
    handle.ensure_running()
    cursor = Cursor(handle.controller.log, since, type, handle.id, WS_BATCH, epoch)
    loop = asyncio.get_running_loop()
    disconnected = loop.create_task(_until_disconnect(websocket))
    deleted: asyncio.Future[None] = loop.create_future()
    cancel = handle.on_close(lambda: deleted.done() or deleted.set_result(None))
    hello = [json.dumps(epoch_message(cursor.log, cursor.reset))]
    # served by uvicorn through motionsim's protocol: once caught up, the log's fan-out
    # writes this subscriber's frames (the same messages; see motionsim.api.ws_fanout)
    write_frames = (websocket.scope.get("extensions") or {}).get(EXTENSION)  # may be None
    try:
        while not disconnected.done():
            texts = hello + cursor.read_text()
            hello = []
            # written at once when the client's buffer is under its high-water mark;
            # otherwise through ASGI, which waits for it to drain
            if texts and (write_frames is None or not write_frames(frames(texts, batch))):
                for text in messages(texts, batch):
                    await websocket.send_text(text)
            if deleted.done():
                await websocket.close(code=CLOSE_DELETED, reason="controller deleted")
                break
            if cursor.behind:
                await asyncio.sleep(0)  # more held: let others run, then continue
            elif write_frames is not None:
                await stream_live(cursor, write_frames, batch, disconnected, deleted)
            else:
                await cursor.wait(disconnected, deleted)
    except (WebSocketDisconnect, RuntimeError, ConnectionError):
        pass
    finally:
        cancel()
        disconnected.cancel()


def _reason(message: str) -> str:
    """A close reason within the protocol's 123 bytes (UTF-8)."""
    data = message.encode()
    if len(data) <= 123:
        return message
    return data[:120].decode(errors="ignore") + "..."


async def _until_disconnect(websocket: WebSocket) -> None:
    """Read (and ignore) client messages until the client goes away."""
    while True:
        message = await websocket.receive()
        if message["type"] == "websocket.disconnect":
            return
