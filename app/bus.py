"""The event bus: each subscriber is a cursor on a controller's event log.

There is no queue per subscriber. A :class:`Cursor` remembers the last ``seq`` it delivered and
reads the log's ring from there, in batches; between batches it sleeps on
``log.wake_on_next`` (one future, resolved by the next ``emit``). Consequences:

- a slow subscriber never blocks the simulation or the other subscribers — it only falls
  behind in the ring;
- memory is bounded by the ring (at least 100 000 events per controller), whatever the number
  or speed of subscribers;
- a subscriber that falls further behind than the ring holds gets a ``gap``
  (``{"type": "gap", "from", "to"}``) and continues with the oldest event still held;
- the stream's first message (sent by the route: :func:`epoch_message`) names the log's
  incarnation: ``{"type": "epoch", "epoch", "first_seq",
  "last_seq", "reset"}``; ``reset`` is ``null``, or — when the subscriber resumed with a stale
  epoch or a ``since`` beyond the log's end — ``{"epoch", "reason", "since", "last_seq"}`` and the
  stream starts again from the beginning of the log;
- an event's JSON text is encoded once for every cursor of its log and controller id
  (:meth:`Cursor.read_text`): a hundred subscribers cost one ``json.dumps`` an event, not a
  hundred.

Used by the WebSocket route; usable by any asyncio consumer::

    cursor = Cursor(log, since=0, types={"breq"}, controller="pmac")
    while True:
        for message in cursor.read():
            ...
        if not cursor.behind:
            await cursor.wait()
"""

from __future__ import annotations

import asyncio
import json
import weakref
from collections.abc import Iterable
from typing import Any

from ..sim.events import Event, EventLog, ReadResult, Reset

#: The shared texts cover the newest this many events of a log (up to twice as many are held
#: between two prunes): what every subscriber that keeps up reads. One further behind encodes
#: its own (the same text, only not shared), without churning the shared ones.
TEXTS_KEPT = 4096


class _Texts:
    """The JSON text of recent events of one log, in the wire form for one controller id."""

    def __init__(self, controller: str | None) -> None:
        self.controller = controller
        self.by_seq: dict[int, str] = {}

    def text(self, event: Event, newest: int) -> str:
        """``event``'s text; shared if it is among the ``TEXTS_KEPT`` before ``newest``."""
        text = self.by_seq.get(event.seq)
        if text is None:
            text = json.dumps(event.to_dict(self.controller))
            oldest = newest - TEXTS_KEPT  # the newest shared text is newer than this
            if event.seq > oldest:
                if len(self.by_seq) >= 2 * TEXTS_KEPT:
                    self.by_seq = {k: v for k, v in self.by_seq.items() if k > oldest}
                self.by_seq[event.seq] = text
        return text


_shared: weakref.WeakKeyDictionary[EventLog, dict[str | None, _Texts]] = (
    weakref.WeakKeyDictionary())


def _texts(log: EventLog, controller: str | None) -> _Texts:
    by_id = _shared.setdefault(log, {})
    texts = by_id.get(controller)
    if texts is None:
        texts = by_id[controller] = _Texts(controller)
    return texts


class Cursor:
    """A subscriber's position in one controller's event log.

    Args:
        log: the controller's event log.
        since: deliver events with ``seq > since``.
        types: only these event types (all if empty / None).
        controller: the id put in each event's wire form.
        batch: events read per :meth:`read` (the route yields to the loop between batches).
        epoch: the log epoch the subscriber's ``since`` belongs to (``None``: not known).
    """

    def __init__(self, log: EventLog, since: int = 0, types: Iterable[str] | None = None,
                 controller: str | None = None, batch: int = 256,
                 epoch: str | None = None) -> None:
        if since < 0:
            raise ValueError("since must be >= 0")
        self.log = log
        #: Set when ``since`` / ``epoch`` belonged to another incarnation of the log (reading
        #: then starts at the beginning of this one).
        self.since, self.reset = log.resume(since, epoch)
        self.types = frozenset(types) if types else None
        self.controller = log.controller if controller is None else controller
        self.batch = batch
        self._texts = _texts(log, self.controller)

    @property
    def behind(self) -> bool:
        """True while the log holds events this cursor has not examined yet."""
        return self.since < self.log.last_seq

    def read(self) -> list[dict[str, Any]]:
        """The next wire messages (a gap first if events were lost), at most ``batch`` events."""
        res = self._take()
        out: list[dict[str, Any]] = []
        if res.gap is not None:
            out.append(res.gap.to_dict())
        cid = self.controller
        out.extend(e.to_dict(cid) for e in res.events)
        return out

    def read_text(self) -> list[str]:
        """:meth:`read`, each message as its JSON text (``json.dumps`` of it), an event's
        text shared with every other cursor of this log and controller id."""
        res = self._take()
        out = [json.dumps(res.gap.to_dict())] if res.gap is not None else []
        text, newest = self._texts.text, self.log.last_seq
        out.extend(text(e, newest) for e in res.events)
        return out

    def _take(self) -> ReadResult:
        """The next batch from the log (a gap first if events were lost); moves past it."""
        res = self.log.read(self.since, self.types, self.batch)
        self.since = res.next
        return res

    async def wait(self, *others: asyncio.Future[Any]) -> None:
        """Sleep until the next event is emitted (or one of ``others`` completes)."""
        if self.behind:
            return
        woken: asyncio.Future[None] = asyncio.get_running_loop().create_future()

        def wake(_: Any = None) -> None:
            if not woken.done():
                woken.set_result(None)

        self.log.wake_on_next(wake)
        for other in others:  # one future, no asyncio.wait: this runs per subscriber per event
            other.add_done_callback(wake)
        try:
            await woken
        finally:
            for other in others:
                other.remove_done_callback(wake)


def epoch_message(log: EventLog, reset: Reset | None = None) -> dict[str, Any]:
    """The stream's first message: the log's epoch, the ``seq`` range it holds, any reset."""
    return {"type": "epoch", "epoch": log.epoch, "first_seq": log.first_seq,
            "last_seq": log.last_seq, "reset": None if reset is None else reset.to_dict()}


__all__ = ["Cursor", "epoch_message"]
