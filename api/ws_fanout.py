"""The event stream's fan-out: one framing per event, written to every caught-up subscriber.

A WebSocket subscriber (``/controllers/{id}/events``) is a :class:`motionsim.app.bus.Cursor`
served by its own task. While the cursor is *behind* (the backlog after ``since``, a burst, a
client whose buffer is full) the task reads and sends through ASGI, which waits for the
client to drain. Once it has caught up, the task hands the cursor to its log's
:class:`Fanout` and sleeps: at the next emitted event the fan-out — one callback on the loop,
not a task per subscriber — reads the new events once per distinct subscription (``since``,
types, controller id, ``batch``), frames them once (:func:`motionsim.api.ws_protocol.text_frame`)
and writes the same bytes to each such subscriber's transport
(:meth:`motionsim.api.ws_protocol.FramedWebSocketProtocol.write_frames`). The messages are the
ones the task would have sent, byte for byte and in the same order: they come from the same
:meth:`Cursor.read_text`, one text frame per message (with ``batch``: one array per read).

The fan-out hands a subscriber back to its task (which then continues exactly where the cursor
is) when it cannot keep the stream's guarantees itself:

- the client's transport is paused by flow control (or closing): the task waits for it to
  drain, so a slow client costs at most one write beyond the high-water mark, then falls
  behind in the ring like any other reader;
- more than one batch (:data:`BATCH`) of events arrived since the last write (a virtual clock
  advancing fast): the task sends them in batches, giving the loop a turn in between;
- the ring has moved past the cursor (a ``gap``, sent by the task);
- the controller was deleted or the client left (the task closes the stream).
"""

from __future__ import annotations

import asyncio
import weakref
from collections.abc import Callable
from typing import Any

from ..app.bus import Cursor
from ..sim.events import EventLog
from .ws_protocol import text_frame

#: Events the fan-out writes to a subscriber at once; more pending: back to its task.
BATCH = 256

#: ``write_frames``: write whole frames now (True) or refuse, writing nothing (False).
WriteFrames = Callable[[bytes], bool]


def messages(texts: list[str], batch: bool) -> list[str]:
    """The stream's messages for ``texts`` (one read of a cursor): one each, or with
    ``batch`` one array of them (byte for byte ``json.dumps`` of the list of messages)."""
    if batch:
        return ["[" + ", ".join(texts) + "]"] if texts else []
    return texts


def frames(texts: list[str], batch: bool) -> bytes:
    """:func:`messages` as the bytes of their text frames (nothing for no texts)."""
    return b"".join([text_frame(m) for m in messages(texts, batch)])


class Live:
    """A caught-up subscriber: its cursor, how to write to it, and how to wake its task."""

    __slots__ = ("batch", "cursor", "woken", "write")

    def __init__(self, cursor: Cursor, write: WriteFrames, batch: bool,
                 woken: asyncio.Future[None]) -> None:
        self.cursor = cursor
        self.write = write
        self.batch = batch
        self.woken = woken

    def wake(self, _: Any = None) -> None:
        """Give the stream back to the subscriber's task."""
        if not self.woken.done():
            self.woken.set_result(None)


class Fanout:
    """The caught-up subscribers of one event log, written to at each emitted event."""

    def __init__(self, log: EventLog, loop: asyncio.AbstractEventLoop) -> None:
        self.log = log
        self.loop = loop
        self.live: dict[Live, None] = {}  # insertion-ordered set
        self._armed = False  # a waker is registered on the log
        self._scheduled = False  # a flush is scheduled on the loop

    def add(self, sub: Live) -> None:
        self.live[sub] = None
        if not self._armed:
            self._armed = True
            self.log.wake_on_next(self._wake)

    def remove(self, sub: Live) -> None:
        self.live.pop(sub, None)

    def _wake(self) -> None:
        """An event was emitted (inside a simulation step): flush once the step is done."""
        self._armed = False
        if not self._scheduled:
            self._scheduled = True
            self.loop.call_soon(self.flush)

    def flush(self) -> None:
        """Write what each caught-up subscriber has not received yet; re-arm."""
        self._scheduled = False
        log = self.log
        last, held_from = log.last_seq, log.first_seq - 1
        built: dict[tuple[Any, ...], tuple[bytes, int]] = {}
        for sub in tuple(self.live):
            cursor = sub.cursor
            since = cursor.since
            if since >= last:
                continue
            if last - since > min(BATCH, cursor.batch) or since < held_from:
                self._hand_back(sub)  # a burst or a gap: the task's careful path
                continue
            key = (since, cursor.types, cursor.controller, sub.batch)
            done = built.get(key)
            if done is None:
                texts = cursor.read_text()  # up to ``last``: at most a batch, checked above
                done = built[key] = (frames(texts, sub.batch), cursor.since)
                cursor.since = since  # moved on below, once written
            data, after = done
            if data and not sub.write(data):
                self._hand_back(sub)  # paused by flow control or closing: nothing written
                continue
            cursor.since = after
        if self.live and not self._armed:
            self._armed = True
            log.wake_on_next(self._wake)

    def _hand_back(self, sub: Live) -> None:
        self.live.pop(sub, None)
        sub.wake()


_fanouts: weakref.WeakKeyDictionary[EventLog, Fanout] = weakref.WeakKeyDictionary()


def fanout_of(log: EventLog) -> Fanout:
    """``log``'s fan-out on the running loop."""
    loop = asyncio.get_running_loop()
    fan = _fanouts.get(log)
    if fan is None or fan.loop is not loop:
        fan = _fanouts[log] = Fanout(log, loop)
    return fan


async def stream_live(cursor: Cursor, write: WriteFrames, batch: bool,
                      *others: asyncio.Future[Any]) -> None:
    """Let ``cursor``'s log's fan-out write to this subscriber until it hands the stream
    back (see the module's list) or one of ``others`` (the client left, the controller was
    deleted) completes. ``cursor`` must have caught up (not ``behind``)."""
    woken: asyncio.Future[None] = asyncio.get_running_loop().create_future()
    sub = Live(cursor, write, batch, woken)
    fan = fanout_of(cursor.log)
    for other in others:
        other.add_done_callback(sub.wake)
    fan.add(sub)
    try:
        await woken
    finally:
        fan.remove(sub)
        for other in others:
            other.remove_done_callback(sub.wake)


__all__ = ["BATCH", "Fanout", "Live", "fanout_of", "frames", "messages", "stream_live"]
