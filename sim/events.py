"""The event log: the one window on a simulated controller.

Everything the outside can see happen — a BREQ edge, a line loaded or calculated, a move
starting, an M-variable write, a Trio process blocking — is an :class:`Event` appended to the
controller's :class:`EventLog`. Tests, the REST and WebSocket API, traces and plots all read
this one log.

``seq`` counts from 1 per controller with no holes; ``t`` is simulated seconds (the
``simpy.Environment``'s ``now``). The log is a bounded ring: it holds at least the last
``capacity`` events, and a reader asking for older ones is told which range it lost
(:class:`Gap`).

Each log has an ``epoch``: an opaque string naming this incarnation of the log. ``seq`` starts
again at 1 whenever a log is created (a service restart, or a controller deleted and created again
under the same id), so a reader resuming with ``since=`` compares epochs to know that its ``seq``
belongs to a log that no longer exists (:meth:`EventLog.resume`). A controller reset (power
cycle) keeps the log, its ``seq`` numbering and its epoch.

The hot path is :meth:`EventLog.emit`: it stores a plain tuple in a preallocated ring and
builds the frozen :class:`Event` value only when somebody reads it, so a stream of a million
lines does not pay for objects nobody looks at.
"""

from __future__ import annotations

import json
import uuid
from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass
from typing import Any

import simpy

#: Decimal places of a simulated instant in the wire form (JSON, JSON Lines, CSV): 1 ns. The
#: core keeps ``t`` as the float SimPy schedules (a sum of servo periods, RTIs and host
#: delays), which carries binary noise such as ``0.0012000000000000001``; the wire form rounds
#: it to the nanosecond, far below a servo cycle (PMAC I10 = 3 713 707: 442.7 us; a Trio's
#: SERVO_PERIOD is whole microseconds), so a reader dividing by the servo period still gets
#: the cycle number, and two instants a cycle apart never meet.
WIRE_TIME_DIGITS = 9


def wire_time(t: float) -> float:
    """A simulated instant as the API writes it: ``t`` rounded to :data:`WIRE_TIME_DIGITS`."""
    return round(t, WIRE_TIME_DIGITS)


#: The event types of API.md and the fields each carries (beyond seq, t, type, controller).
#: Controller kinds may emit further types; they document them here.
EVENT_FIELDS: dict[str, tuple[str, ...]] = {
    "breq": ("cs", "level"),
    "line_loaded": ("cs", "n", "text", "words", "lines_ahead"),
    "line_calculated": ("cs", "n"),
    "move_start": ("cs|axis", "n|mtype"),
    "move_end": ("cs|axis", "n|mtype"),
    "mvar": ("name", "value", "sync"),
    "pset": ("cs", "n", "positions"),  # PMAC: PSET gave these axes new present positions
    "program_error": ("cs", "prog", "n", "reason"),  # PMAC: control flow's run-time error
    "kinematics": ("cs", "program", "error"),  # PMAC: a kinematic program gave no result
    "pmatch": ("cs", "axes"),  # PMAC: axis positions re-computed from the motors
    "ubuffer": ("first", "last"),  # PMAC: DEFINE UBUFFER / DELETE ALL (None, None)
    "undefine": ("cs",),  # PMAC: UNDEFINE (cs None: UNDEFINE ALL)
    "program": ("cs|process", "state", "error"),  # PMAC error: "run_time_error" / "watchdog"
    "axis": ("axis", "mtype", "ntype"),
    "process_buffer": ("process", "axis", "mtype"),
    "process": ("process", "state", "line", "blocked_on", "error"),
    "terminal": ("locked",),
    "terminal_reply": ("command", "reply", "error"),
    "plc": ("plc", "state"),  # PMAC: ``compiled: True`` too for a PLCC
    "plc_send": ("plc", "port", "text"),  # PMAC: a PLC's SEND"..." line (port S/P/R/A/host)
    "program_send": ("cs", "line", "port", "text"),  # PMAC: a motion program's SEND"..." line
    "host_message_dropped": ("source", "port", "text", "dropped"),  # PMAC: a SEND line lost
    "gather": ("state", "reason|sources", "samples|period"),  # PMAC: gathering started/stopped
    "timer": ("var", "value"),  # PMAC: an Isx11/Isx12 countdown timer was written (cycles)
    "rti_overrun": ("over_s",),
    "watchdog": ("reason",),
    "reset": (),
    "print": ("process", "channel", "text"),  # Trio: a line a BASIC program printed
    "scope": ("state", "period", "samples"),  # Trio: SCOPE armed / triggered / done / off
    # scenario host models (sim/hosts/): what the simulated host did and saw
    "host_write": ("host", "cs", "lines", "sent"),
    "host_timeout": ("host", "cs", "command"),
    "host_pr": ("host", "cs", "lines_ahead", "reply_s"),
    "host_irq": ("host", "cs", "missed", "latency_s"),
    "host_blocked": ("host",),
    "host_resumed": ("host",),
    "host_done": ("host",),
    "host_stopped": ("host",),
    "cpu_sample": ("servo", "rti", "background"),
    "jog": ("motor", "state", "command", "position"),  # PMAC: a jog / home move starts / ends
    "home": ("motor", "state", "position"),  # PMAC: a home search found its trigger
    "motor": ("motor", "state"),  # PMAC: servo loop closed / opened / killed
    # the service's realtime clock: it fell behind its schedule / caught up (app/clock.py)
    "clock_lag": ("lag_s", "behind"),
    # an injected fault took effect (sim/faults.py, app/faults.py)
    "fault": ("fault", "kind", "command|cs|start_s", "end_s|error"),
}


@dataclass(frozen=True, slots=True)
class Event:
    """One observable change: sequence number, simulated time, type and fields."""

    seq: int
    t: float
    type: str
    fields: Mapping[str, Any]

    def __getitem__(self, key: str) -> Any:
        return self.fields[key]

    def get(self, key: str, default: Any = None) -> Any:
        return self.fields.get(key, default)

    def matches(self, pattern: Mapping[str, Any]) -> bool:
        """True when ``pattern["type"]`` (if given) and every other key equal this event's."""
        for key, want in pattern.items():
            if key == "type":
                if self.type != want:
                    return False
            elif key not in self.fields or self.fields[key] != want:
                return False
        return True

    def to_dict(self, controller: str | None = None) -> dict[str, Any]:
        """The wire form: ``{"seq", "t", "type", "controller"?, ...fields}``."""
        out: dict[str, Any] = {"seq": self.seq, "t": wire_time(self.t), "type": self.type}
        if controller is not None:
            out["controller"] = controller
        out.update(self.fields)
        return out


@dataclass(frozen=True, slots=True)
class Gap:
    """Events ``from_seq`` .. ``to_seq`` (inclusive) left the ring before being read."""

    from_seq: int
    to_seq: int

    def to_dict(self) -> dict[str, Any]:
        return {"type": "gap", "from": self.from_seq, "to": self.to_seq}


@dataclass(frozen=True, slots=True)
class Reset:
    """A resume position that does not belong to this log: the reader must start again.

    ``reason``: ``"stale_epoch"`` (the reader's epoch names an earlier incarnation of the log)
    or ``"since_beyond_end"`` (its ``since`` is past the newest ``seq``: the log it read was
    longer, so it was another one). Reading continues from the start of this log.
    """

    epoch: str
    reason: str
    since: int
    last_seq: int

    def to_dict(self) -> dict[str, Any]:
        return {"epoch": self.epoch, "reason": self.reason, "since": self.since,
                "last_seq": self.last_seq}


@dataclass(frozen=True, slots=True)
class ReadResult:
    """What :meth:`EventLog.read` returns: the events, a gap if any, and where to continue."""

    events: list[Event]
    gap: Gap | None
    next: int


Listener = Callable[[Event], None]


def _event(rec: tuple[Any, ...]) -> Event:
    """The :class:`Event` of a ring record: ``(seq, t, type, fields)`` or, from
    :meth:`EventLog.emit_row`, ``(seq, t, type, keys, values)``."""
    if len(rec) == 4:
        return Event(*rec)
    return Event(rec[0], rec[1], rec[2], dict(zip(rec[3], rec[4], strict=True)))


class EventLog:
    """Append-only, bounded, sequence-numbered log of one controller's events.

    Args:
        env: the controller's environment; its ``now`` stamps every event.
        controller: the controller id, added to the wire form of each event.
        capacity: how many of the newest events are held (at least 100 000 in the service).
        epoch: this incarnation's name (default: a fresh random one, unique across restarts).
    """

    def __init__(self, env: simpy.Environment, controller: str = "", capacity: int = 100_000,
                 epoch: str | None = None):
        if capacity < 1:
            raise ValueError("capacity must be >= 1")
        #: Opaque name of this incarnation of the log; never equal to an earlier one's.
        self.epoch = epoch if epoch is not None else uuid.uuid4().hex[:16]
        self._env = env
        self.controller = controller
        self.capacity = capacity
        #: The held events, grown to ``capacity`` as they come (an idle controller's log
        #: holds nothing: 100 000 empty slots were 0.8 MB a controller), then a ring.
        #: A record is ``(seq, t, type, fields)`` (:meth:`emit`) or ``(seq, t, type, keys,
        #: values)`` (:meth:`emit_row`); :func:`_event` makes the :class:`Event` of either.
        self._ring: list[tuple[Any, ...]] = []
        self._last = 0
        self._listeners: list[Listener] = []
        self._wakers: list[Callable[[], None]] = []
        #: Someone listens or waits: ``bool(self._listeners or self._wakers)``, kept by
        #: :meth:`listen`, its unsubscribe, :meth:`wake_on_next` and :meth:`_tell`.
        self._told = False

    # -- writing -------------------------------------------------------------------------

    def emit(self, type_: str, /, **fields: Any) -> int:
        """Append an event stamped with the current simulated time; return its ``seq``."""
        self._last = seq = self._last + 1
        rec = (seq, self._env._now, type_, fields)  # _now: no property call (hot path)
        if seq <= self.capacity:
            self._ring.append(rec)  # seq - 1 == len(ring): the ring still growing
        else:
            self._ring[(seq - 1) % self.capacity] = rec
        if self._told:  # (one test for the usual case: nobody listening or waiting)
            self._tell(rec)
        return seq

    def emit_row(self, type_: str, keys: tuple[str, ...], values: tuple[Any, ...], /) -> int:
        """:meth:`emit` of the fields ``dict(zip(keys, values))``, stored as the two tuples:
        the dict is made only when the event is read (the per-line events of a stream, most
        of which nobody reads before the ring drops them). The same event, byte for byte."""
        self._last = seq = self._last + 1
        rec = (seq, self._env._now, type_, keys, values)
        if seq <= self.capacity:
            self._ring.append(rec)
        else:
            self._ring[(seq - 1) % self.capacity] = rec
        if self._told:
            self._tell(rec)
        return seq

    def _tell(self, rec: tuple[Any, ...]) -> None:
        """The listeners and the one-shot wakers of :meth:`emit`'s new event ``rec``."""
        if self._listeners:
            event = _event(rec)
            for listener in tuple(self._listeners):
                listener(event)
        if self._wakers:
            wakers, self._wakers = self._wakers, []
            for wake in wakers:
                wake()
        self._told = bool(self._listeners or self._wakers)

    @property
    def observed(self) -> bool:
        """Someone listens (:meth:`listen`) or waits (:meth:`wake_on_next`): each event is
        told to them as it is emitted."""
        return self._told

    # -- reading -------------------------------------------------------------------------

    @property
    def last_seq(self) -> int:
        """The newest ``seq`` (0 before the first event)."""
        return self._last

    @property
    def first_seq(self) -> int:
        """The oldest ``seq`` still held (``last_seq + 1`` when empty)."""
        return max(1, self._last - self.capacity + 1) if self._last else 1

    def resume(self, since: int, epoch: str | None = None) -> tuple[int, Reset | None]:
        """Where a reader resuming at ``since`` (of log ``epoch``, if it knows it) continues.

        ``(since, None)`` when the position belongs to this log; ``(0, Reset)`` when it cannot:
        ``epoch`` is not this log's, or ``since`` is beyond the newest ``seq``.
        """
        since = max(0, since)
        if epoch is not None and epoch != self.epoch:
            reason = "stale_epoch"
        elif since > self._last:
            reason = "since_beyond_end"
        else:
            return since, None
        return 0, Reset(self.epoch, reason, since, self._last)

    def read(
        self,
        since: int = 0,
        types: Iterable[str] | None = None,
        limit: int | None = None,
    ) -> ReadResult:
        """Events with ``seq > since``, oldest first, filtered by ``types``, at most ``limit``.

        ``next`` is the ``since`` to pass to continue: after the last event returned, or — when
        the type filter skipped events — after the last event examined.
        """
        since = max(0, since)
        first = self.first_seq
        gap = Gap(since + 1, first - 1) if since + 1 < first else None
        start = max(since + 1, first)
        wanted = frozenset(types) if types else None
        out: list[Event] = []
        cap = self.capacity
        ring = self._ring
        seq = start
        nxt = since if gap is None else first - 1
        while seq <= self._last:
            if limit is not None and len(out) >= limit:
                break
            rec = ring[(seq - 1) % cap]
            if wanted is None or rec[2] in wanted:
                out.append(_event(rec))
            nxt = seq
            seq += 1
        return ReadResult(out, gap, nxt)

    def held_types(self) -> set[str]:
        """The types of the events held in the ring (a scan: for rare checks, not hot paths)."""
        return {rec[2] for rec in self._ring}

    def events(self, *types: str) -> list[Event]:
        """Every held event (of the given types, if any): the test's view of the log."""
        return self.read(0, types or None).events

    def __iter__(self) -> Iterator[Event]:
        return iter(self.events())

    def __len__(self) -> int:
        return self._last - self.first_seq + 1

    # -- subscribing ---------------------------------------------------------------------

    def listen(self, listener: Listener) -> Callable[[], None]:
        """Call ``listener`` synchronously with every new event; returns an unsubscribe."""
        self._listeners.append(listener)
        self._told = True

        def unsubscribe() -> None:
            if listener in self._listeners:
                self._listeners.remove(listener)
                self._told = bool(self._listeners or self._wakers)

        return unsubscribe

    def wake_on_next(self, wake: Callable[[], None]) -> None:
        """Call ``wake()`` once, at the next emitted event (a cheap no-polling wake-up)."""
        self._wakers.append(wake)
        self._told = True

    # -- export --------------------------------------------------------------------------

    def to_jsonl(self, controller: str | None = None) -> str:
        """The held log as JSON Lines, byte-identical for identical runs."""
        name = self.controller if controller is None else controller
        return "".join(
            json.dumps(e.to_dict(name), separators=(",", ":"), sort_keys=False) + "\n"
            for e in self.events()
        )


__all__ = ["EVENT_FIELDS", "WIRE_TIME_DIGITS", "Event", "EventLog", "Gap", "ReadResult",
           "Reset", "wire_time"]
