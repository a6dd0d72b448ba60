"""The controller base: one ``simpy.Environment``, one event log, a command line.

A controller kind (PMAC, Trio, ...) subclasses :class:`Controller`. Its public methods are the
controller's own commands; everything observable goes to ``self.log``. The core never reads
the wall clock and never does I/O: time moves only when somebody steps ``self.env``
(``app/clock.py`` does, virtually or paced to the wall clock).

Host ports: a real controller talks to several hosts at once (the PMAC's serial, bus and each
Ethernet connection; the Trio's channels). Each is a :class:`Port` with state of its own
(addressed coordinate system / motor, open buffer). The REST terminal is one port; each TCP
connection opens another.

Terminal replies are :class:`Reply` futures, because a controller answers in its own time: a
Turbo PMAC answers a host command in its background cycle, a Trio command line that has
locked on a move answers when the move is buffered.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from typing import Any, ClassVar

import simpy

from .errors import NotFound
from .events import EVENT_FIELDS, EventLog
from .recording import Recording


class Reply:
    """The future answer to one command-line command.

    ``reply`` is the data the controller sends back (PMAC: data lines joined with ``"\\r"``,
    no handshake characters); ``error`` is the controller's error code (``"ERR003"``) or
    message, or ``None``; ``detail`` is ``(kind, message)`` explaining the error for a
    person (``("not_simulated", "...")``), or ``None``.
    """

    __slots__ = ("command", "reply", "error", "detail", "done", "t_done", "answered_pending",
                 "_callbacks")

    def __init__(self, command: str) -> None:
        self.command = command
        self.reply = ""
        self.error: str | None = None
        self.detail: tuple[str, str] | None = None
        self.done = False
        self.t_done: float | None = None
        #: the host was answered "pending": before this completed, or (a realtime clock) it
        #: completed later than the terminal's simulated wait; a kind announces the
        #: completion as a ``terminal_reply`` event (API.md, "The terminal")
        self.answered_pending = False
        self._callbacks: list[Callable[[Reply], None]] = []

    def resolve(self, reply: str = "", error: str | None = None, t: float | None = None) -> None:
        """Complete the reply (once); runs the done-callbacks."""
        if self.done:
            return
        self.reply, self.error, self.done, self.t_done = reply, error, True, t
        callbacks, self._callbacks = self._callbacks, []
        for cb in callbacks:
            cb(self)

    def add_done_callback(self, cb: Callable[[Reply], None]) -> None:
        """Call ``cb(self)`` when done (at once if already done)."""
        if self.done:
            cb(self)
        else:
            self._callbacks.append(cb)

    def __repr__(self) -> str:
        state = f"reply={self.reply!r} error={self.error!r}" if self.done else "pending"
        return f"<Reply {self.command!r} {state}>"


class Port:
    """One host connection to the controller, with its own modal state.

    Controller kinds keep per-port state in ``state`` (PMAC: addressed ``&n`` / ``#n``, the
    buffer this port holds open). ``name`` is for messages and traces only.
    """

    __slots__ = ("name", "state", "closed")

    def __init__(self, name: str) -> None:
        self.name = name
        self.state: dict[str, Any] = {}
        self.closed = False

    def __repr__(self) -> str:
        return f"<Port {self.name}>"


class Controller:
    """Base of every simulated controller kind.

    Args:
        id: the controller's id in the service (``"pmac"``).
        config: initial settings of the kind (PMAC I-variables such as ``{"i16": 5}``, Trio
            ``{"servo_period_ms": 1.0}``). A kind rejects keys it does not know with
            :class:`motionsim.sim.errors.InvalidValue` naming the field.
        log_capacity: events held in the ring (at least 100 000 in the service).
    """

    #: The kind's name in ``POST /controllers {"kind": ...}``.
    kind: ClassVar[str] = "base"

    #: Event types this kind emits beyond :data:`motionsim.sim.events.EVENT_FIELDS`.
    event_types: ClassVar[tuple[str, ...]] = ()

    def __init__(
        self,
        id: str,
        config: Mapping[str, Any] | None = None,
        *,
        log_capacity: int = 100_000,
    ) -> None:
        self.id = id
        self.config: dict[str, Any] = dict(config or {})
        self.env = simpy.Environment()
        self.log = EventLog(self.env, id, log_capacity)
        self.rest_port = self.open_port("rest")

    @property
    def now(self) -> float:
        """Current simulated time in seconds."""
        return self.env.now

    # -- host ports and the command line ---------------------------------------------------

    def open_port(self, name: str) -> Port:
        """A new host port (one per TCP connection; the REST terminal has its own)."""
        return Port(name)

    def close_port(self, port: Port) -> None:
        """The host went away: release what the port held (e.g. an open PMAC buffer)."""
        port.closed = True

    def terminal(self, command: str, port: Port | None = None) -> Reply:
        """Send one line to the controller's command line; the reply may come later."""
        raise NotImplementedError

    # -- variables -------------------------------------------------------------------------

    def get_variable(self, name: str) -> float:
        """Read a variable by its controller name (PMAC ``I16``, ``P5``, ``M1``; Trio ``VR(5)``).

        Raises:
            sim.errors.NotFound: the kind has no such variable.
        """
        raise NotImplementedError

    def set_variable(self, name: str, value: float) -> None:
        """Write a variable at the current simulated instant (as an on-line command would)."""
        raise NotImplementedError

    def recording(self) -> Recording:
        """The controller's own recording (PMAC data gathering, Trio SCOPE: sim.recording).

        Raises:
            sim.errors.NotFound: the kind records nothing.
        """
        raise NotFound(f"a {self.kind} controller has no recording")

    # -- life cycle ------------------------------------------------------------------------

    def reset(self) -> None:
        """Power cycle: factory defaults, buffers and programs gone. Time goes on."""
        raise NotImplementedError

    def known_event_types(self) -> list[str]:
        """Every event type a subscriber may ask for: API.md's, the kind's, any held in the log."""
        known = set(EVENT_FIELDS) | set(self.event_types)
        return sorted(known | self.log.held_types())

    def unknown_event_types(self, types: Iterable[str]) -> list[str]:
        """The names in ``types`` that are no event type of this controller (see above)."""
        static = set(EVENT_FIELDS) | set(self.event_types)
        rest = [t for t in types if t not in static]
        if rest:
            held = self.log.held_types()
            rest = [t for t in rest if t not in held]
        return rest

    def status(self) -> dict[str, Any]:
        """Kind-specific summary for ``GET /controllers/{id}`` (JSON-able)."""
        return {}


__all__ = ["Controller", "Port", "Reply"]
