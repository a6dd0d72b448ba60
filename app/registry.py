"""The running controllers of one service, each with the clock that drives it.

A :class:`ControllerHandle` is what routes, protocol listeners and scenarios hold: the
simulated controller (routes call only its public methods), its clock, and the two ways in
that respect the time model — :meth:`ControllerHandle.command` (the terminal, with API.md's
timing rules) and :meth:`ControllerHandle.apply` (any other mutation, at the current instant).
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import contextlib
import re
from collections.abc import Callable, Iterator, Mapping
from typing import Any, TypeVar

from ..sim.controller import Controller, Port, Reply
from ..sim.errors import Conflict, InvalidValue, NotFound
from ..sim.events import Event
from ..sim.simpy_adapter import cancel, wake_at
from .clock import (
    RUN_UNTIL_WALL_S,
    Clock,
    ClockMode,
    DrivenClock,
    RealtimeClock,
    VirtualClock,
    make_clock,
    reply_steps,
)
from .faults import faults_of, has_faults
from .host_paced import DEFAULT_HOLDER, HostPacedClock
from .inflight import InFlight
from .kinds import kind_class

T = TypeVar("T")

#: Default simulated seconds a virtual clock may run forward waiting for a terminal reply
#: (API.md: "if no reply comes within 1 s of simulated time ... pending"). A kind whose
#: command line answers at the current instant and never moves the clock (Trio) sets the
#: class attribute ``terminal_wait_s = 0``.
TERMINAL_WAIT_S = 1.0

#: Wall seconds a realtime terminal command waits for its reply before answering "pending".
REALTIME_REPLY_CAP_S = 5.0

#: Wall seconds a realtime or host-paced run-until waits at most (the clocks' own cap).
RUN_UNTIL_WALL_CAP_S = RUN_UNTIL_WALL_S

AnyClock = VirtualClock | RealtimeClock | HostPacedClock

_ID = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,63}$")


def _running_on(loop: asyncio.AbstractEventLoop) -> bool:
    """True when called from code running on ``loop``."""
    try:
        return asyncio.get_running_loop() is loop
    except RuntimeError:
        return False


def _answered(reply: Reply) -> Reply:
    """Mark a reply the host is about to be told is pending, so its completion is announced."""
    if not reply.done:
        reply.answered_pending = True
    return reply


class ControllerHandle:
    """One running controller in the service.

    Attributes:
        id: the controller's id (``"pmac"``).
        kind: its kind (``"pmac"``, ``"trio"``, ...).
        controller: the simulation object.
        clock: the :class:`VirtualClock`, :class:`RealtimeClock` or :class:`HostPacedClock`
            driving its environment.
    """

    def __init__(self, id: str, kind: str, controller: Controller, clock: AnyClock) -> None:
        self.id = id
        self.kind = kind
        self.controller = controller
        self.clock = clock
        self.realtime_reply_cap_s = REALTIME_REPLY_CAP_S
        self.closed = False
        #: The calls waiting on this controller's simulation (cancelled when it is deleted).
        self.inflight = InFlight(id)
        self._on_close: list[Callable[[], None]] = []
        #: The event loop that owns this controller (its clock task, its routes).
        self.loop: asyncio.AbstractEventLoop | None = None

    @property
    def terminal_wait_s(self) -> float:
        """Simulated seconds the terminal may wait for a reply (the kind's ``terminal_wait_s``)."""
        return float(getattr(self.controller, "terminal_wait_s", TERMINAL_WAIT_S))

    # -- the two ways in ---------------------------------------------------------------------

    async def command(self, command: str, port: Port | None = None) -> Reply:
        """Send one terminal line and return its :class:`Reply` per API.md's timing rules.

        The environment is first brought to the current instant (realtime). A reply that is
        done at once is returned as is. Otherwise, if the kind lets its terminal wait
        (``terminal_wait_s > 0``, the PMAC answering in its background cycle): a virtual or
        host-paced clock steps the simulation until the reply (at most ``terminal_wait_s``
        simulated, in slices that give the loop a turn; on a host-paced clock this is part of
        the caller's action, and holders due meanwhile act at its end); a realtime clock awaits
        it (at most ``realtime_reply_cap_s`` wall). A reply still not done is returned pending;
        the kind emits ``terminal_reply`` when it completes. Deleting the controller meanwhile
        ends the wait with :class:`~motionsim.app.inflight.ControllerDeleted`.
        """
        self.ensure_running()
        port = port if port is not None else self.controller.rest_port
        clock = self.clock
        clock.sync()
        if has_faults(self.controller):
            forced = faults_of(self.controller).forced_error(command)
            if forced is not None:  # an injected error_reply: answered, not executed
                reply = Reply(command)
                reply.resolve("", forced, t=self.controller.now)
                return reply
        reply = self.controller.terminal(command, port)
        if reply.done:
            clock.wake()
            return reply
        wait_s = self.terminal_wait_s
        if not isinstance(clock, RealtimeClock):
            if wait_s > 0 and not clock.paused:
                await self.run_until_reply(reply, wait_s)
            clock.wake()
            return _answered(reply)
        clock.wake()
        if wait_s <= 0 or clock.paused:
            return _answered(reply)
        return await self._await_realtime_reply(reply, wait_s)

    async def _await_realtime_reply(self, reply: Reply, wait_s: float) -> Reply:
        """A realtime clock's terminal wait: until the reply is done or ``wait_s`` of
        *simulated* time has passed since the command, whichever is first (at most
        ``realtime_reply_cap_s`` of wall time). A reply done later than ``wait_s`` simulated
        after the command is answered pending, as on a virtual clock — the kind announces it
        as a ``terminal_reply`` event by the same simulated rule (the PMAC's ``terminal``) —
        so how late the machine woke this coroutine cannot change the answer."""
        env = self.controller.env
        t0 = env.now
        done = asyncio.get_running_loop().create_future()

        def _done(_: object) -> None:
            if not done.done():
                done.set_result(None)

        reply.add_done_callback(_done)
        given_up = wake_at(env, t0 + wait_s, _done)
        try:
            with contextlib.suppress(TimeoutError):
                await self.inflight.run(asyncio.wait_for(done, timeout=self.realtime_reply_cap_s))
        finally:
            cancel(given_up)
        if reply.done and reply.t_done is not None and reply.t_done - t0 > wait_s + 1e-9:
            reply.answered_pending = True  # done too late: the host is told "pending"
        return _answered(reply)

    async def run_until_reply(self, reply: Reply, max_s: float) -> None:
        """Virtual or host-paced: step (in slices) until ``reply`` is done, at most ``max_s``
        simulated seconds. The way a REST call that waits for the controller moves time."""
        clock = self.clock
        if isinstance(clock, RealtimeClock):
            raise Conflict("a realtime clock is not stepped by its callers")
        await self.inflight.run_sliced(reply_steps(clock.env, reply, max_s, clock.slice_s))

    async def advance(self, seconds: float, holder: str | None = None) -> None:
        """Virtual: run forward by ``seconds`` (in slices). Host-paced: holder ``holder``
        (default ``main``) waits ``seconds`` of simulated time while the other holders act.
        Realtime: 409 ``conflict``. Deleting the controller meanwhile ends it (410)."""
        await self.inflight.run(self._advance(seconds, holder))

    async def _advance(self, seconds: float, holder: str | None) -> None:
        clock = self.clock
        if isinstance(clock, VirtualClock):
            await clock.advance_async(seconds)
        elif isinstance(clock, HostPacedClock):
            _, outcome = await clock.wait(holder or DEFAULT_HOLDER, None, seconds,
                                          wall_timeout_s=RUN_UNTIL_WALL_CAP_S)
            if outcome == "wall_timeout":
                raise Conflict(
                    f"time did not reach the target within {RUN_UNTIL_WALL_CAP_S:g} s of wall "
                    f"time: held by {', '.join(clock.held_by()) or 'nobody'}",
                    held_by=clock.held_by())
        else:
            raise Conflict("a realtime clock cannot be advanced; PATCH its mode to virtual first")

    async def run_until(self, pattern: Mapping[str, Any], timeout_s: float,
                        holder: str | None = None) -> Event | None:
        """The first *new* event matching ``pattern`` (``{"type": ..., field: value}``).

        Virtual: runs the simulation (in slices) until it is emitted (the clock stops at its
        instant) or ``timeout_s`` simulated seconds pass. Host-paced: holder ``holder`` waits for
        it; the clock holds ``reaction_s`` after it (see :mod:`motionsim.app.host_paced`).
        Realtime: waits for it, at most ``timeout_s`` simulated seconds and at most
        ``RUN_UNTIL_WALL_CAP_S`` wall seconds. ``None`` if no match.
        """
        return (await self.run_until_outcome(pattern, timeout_s, holder))[0]

    async def run_until_outcome(self, pattern: Mapping[str, Any], timeout_s: float,
                                holder: str | None = None) -> tuple[Event | None, str]:
        """:meth:`run_until` with how it ended: ``matched``, ``timeout`` (``timeout_s`` of
        simulated time passed), ``wall_timeout`` (``RUN_UNTIL_WALL_CAP_S`` of wall time passed
        first) or (host-paced) ``released``. Deleting the controller meanwhile ends it (410)."""
        return await self.inflight.run(self._run_until_outcome(pattern, timeout_s, holder))

    async def _run_until_outcome(self, pattern: Mapping[str, Any], timeout_s: float,
                                 holder: str | None) -> tuple[Event | None, str]:
        clock = self.clock
        log = self.controller.log
        if isinstance(clock, VirtualClock):
            start = clock.env.now
            found = await clock.run_until_async(log, pattern, timeout_s,
                                                wall_budget_s=RUN_UNTIL_WALL_CAP_S)
            if found is not None:
                return found, "matched"
            # a simulated time-out leaves the clock at start + timeout_s; the wall budget
            # stops it where it got to, short of that
            reached = clock.env.now >= start + float(timeout_s) - 1e-9
            return None, "timeout" if reached else "wall_timeout"
        if isinstance(clock, HostPacedClock):
            return await clock.wait(holder or DEFAULT_HOLDER, pattern, timeout_s,
                                    wall_timeout_s=RUN_UNTIL_WALL_CAP_S)
        self.ensure_running()
        clock.sync()
        found_f: asyncio.Future[Event] = asyncio.get_running_loop().create_future()

        def listener(event: Event) -> None:
            if not found_f.done() and event.matches(pattern):
                found_f.set_result(event)

        unlisten = log.listen(listener)
        try:
            wall = timeout_s if clock.paused else timeout_s / clock.factor
            cap = min(wall, RUN_UNTIL_WALL_CAP_S)
            return await asyncio.wait_for(found_f, timeout=cap), "matched"
        except TimeoutError:
            return None, "timeout" if wall <= RUN_UNTIL_WALL_CAP_S else "wall_timeout"
        finally:
            unlisten()

    def apply(self, fn: Callable[..., T], *args: Any, **kwargs: Any) -> T:
        """Run a mutation (``fn(*args, **kwargs)``) at the current simulated instant.

        A realtime environment is first run to the wall instant, and the clock is woken
        afterwards because the mutation may have scheduled something sooner. Never moves a
        virtual clock. Safe to call from any thread: off the controller's loop it is run on
        that loop (``call_soon_threadsafe``) and this call waits for the result.
        """
        loop = self.loop
        if loop is not None and not _running_on(loop) and loop.is_running():
            return self._apply_on(loop, fn, args, kwargs)
        self.ensure_running()
        self.clock.sync()
        try:
            return fn(*args, **kwargs)
        finally:
            self.clock.wake()

    def _apply_on(self, loop: asyncio.AbstractEventLoop, fn: Callable[..., T],
                  args: tuple[Any, ...], kwargs: dict[str, Any]) -> T:
        """Called from another thread (e.g. a FastAPI worker thread running a plain ``def``
        route): hand the mutation to the owning loop and wait for its result, so the
        simulation is only ever touched between steps, on its one loop."""
        result: concurrent.futures.Future[T] = concurrent.futures.Future()

        def run() -> None:
            if not result.set_running_or_notify_cancel():
                return
            try:
                result.set_result(self.apply(fn, *args, **kwargs))
            except BaseException as exc:
                result.set_exception(exc)

        loop.call_soon_threadsafe(run)
        return result.result()

    def open_port(self, name: str) -> Port:
        """A new host port on the controller (one per TCP connection)."""
        return self.apply(self.controller.open_port, name)

    def close_port(self, port: Port) -> None:
        """The host went away: the controller releases what the port held."""
        self.apply(self.controller.close_port, port)

    # -- clock -------------------------------------------------------------------------------

    def ensure_running(self) -> None:
        """Bind to the running loop (the first one seen) and start a realtime clock's task."""
        try:
            loop = asyncio.get_running_loop()
        except RuntimeError:
            return
        if self.loop is None or self.loop.is_closed():
            self.loop = loop
        clock = self.clock
        if isinstance(clock, DrivenClock) and not clock.running:
            clock.start()

    async def set_clock(self, mode: ClockMode | None = None, *, factor: float | None = None,
                        paused: bool | None = None, reaction_s: float | None = None,
                        holders: list[str] | None = None) -> None:
        """Change factor / paused (/ a host-paced clock's ``reaction_s``, register ``holders``),
        or switch between virtual, realtime and host-paced at the current t.

        Switching validates everything first: a bad value changes nothing.
        """
        old = self.clock
        if mode is not None and mode != old.mode:
            new = make_clock(mode, self.controller.env,
                             old.factor if factor is None else factor,
                             old.paused if paused is None else paused,
                             log=self.controller.log,
                             reaction_s=_reaction_of(old) if reaction_s is None else reaction_s)
            if isinstance(new, HostPacedClock):
                for name in holders or ():
                    new.hold(name)
            elif holders:
                _close_clock(new)
                raise InvalidValue("holders need a host-paced clock", field="holders")
            old.sync()
            await old.stop()
            _close_clock(old)
            self.clock = new
            self.ensure_running()
            return
        if isinstance(old, HostPacedClock):
            for name in holders or ():
                old.hold(name)
            old.set(factor=factor, paused=paused, reaction_s=reaction_s)
            return
        if reaction_s is not None or holders:
            raise InvalidValue("reaction_s and holders belong to a host-paced clock",
                               field="reaction_s" if reaction_s is not None else "holders")
        old.set(factor=factor, paused=paused)

    def on_close(self, callback: Callable[[], None]) -> Callable[[], None]:
        """Call ``callback()`` when the controller is deleted; returns an unsubscribe."""
        if self.closed:
            callback()
        else:
            self._on_close.append(callback)

        def cancel() -> None:
            if callback in self._on_close:
                self._on_close.remove(callback)

        return cancel

    async def close(self) -> None:
        """End the calls waiting on it (410), stop the clock's task, tell subscribers
        (WebSockets, TCP connections) the controller is gone."""
        self.closed = True
        await self.inflight.close()
        callbacks, self._on_close = self._on_close, []
        for callback in callbacks:
            callback()
        await self.clock.stop()
        _close_clock(self.clock)

    def snapshot(self) -> dict[str, Any]:
        """:meth:`to_dict` at the current instant (a realtime environment is run to it first)."""
        return self.apply(self.to_dict)

    def to_dict(self) -> dict[str, Any]:
        """The API's ``Controller``: id, kind, clock, merged with the kind's ``status()``."""
        out: dict[str, Any] = {}
        out.update(self.controller.status())
        out.update({"id": self.id, "kind": self.kind, "clock": self.clock.to_dict()})
        return out

    def __repr__(self) -> str:
        return f"<ControllerHandle {self.id} kind={self.kind} clock={self.clock.mode}>"


def _reaction_of(clock: Clock) -> float:
    return clock.reaction_s if isinstance(clock, HostPacedClock) else 0.0


def _close_clock(clock: Clock) -> None:
    if isinstance(clock, HostPacedClock):
        clock.close()


class LiveHandle:
    """The controller *currently* registered under ``id``, looked up at each use.

    What the TCP protocol listeners hold: a controller deleted and created again under the
    same id is served by its new incarnation from the next connection on (no "ghost" driving
    the deleted object). Attribute access is forwarded to the current handle; :meth:`current`
    returns it (raises :class:`NotFound` while there is none).
    """

    def __init__(self, registry: Registry, id: str) -> None:
        self._registry = registry
        self.id = id

    def current(self) -> ControllerHandle:
        return self._registry.get(self.id)

    def __getattr__(self, name: str) -> Any:
        return getattr(self.current(), name)

    def __repr__(self) -> str:
        return f"<LiveHandle {self.id}>"


class Registry:
    """The running controllers by id.

    Args:
        log_capacity: events each controller's log holds (at least 100 000 in the service).
        max_controllers: how many may exist at once (the setting ``max_controllers``).
    """

    def __init__(self, *, log_capacity: int = 100_000, max_controllers: int = 64) -> None:
        self.log_capacity = log_capacity
        self.max_controllers = max_controllers
        self._handles: dict[str, ControllerHandle] = {}
        self._started = False

    def get(self, id: str) -> ControllerHandle:
        """The handle of controller ``id``; raises :class:`NotFound`."""
        try:
            handle = self._handles[id]
        except KeyError:
            raise NotFound(f"no controller {id!r}; running: {', '.join(self._handles) or 'none'}",
                           controller=id) from None
        return handle

    def live(self, id: str) -> LiveHandle:
        """A :class:`LiveHandle` for ``id`` (for listeners that outlive one incarnation)."""
        return LiveHandle(self, id)

    def __iter__(self) -> Iterator[ControllerHandle]:
        return iter(list(self._handles.values()))

    def __len__(self) -> int:
        return len(self._handles)

    def __contains__(self, id: object) -> bool:
        return id in self._handles

    def ids(self) -> list[str]:
        return list(self._handles)

    def _new_id(self, kind: str) -> str:
        n = 1
        while f"{kind}{n}" in self._handles:
            n += 1
        return f"{kind}{n}"

    def add(
        self,
        kind: str,
        id: str | None = None,
        *,
        clock: ClockMode = "realtime",
        factor: float = 1.0,
        paused: bool = False,
        config: Mapping[str, Any] | None = None,
        reaction_s: float = 0.0,
        holders: list[str] | None = None,
    ) -> ControllerHandle:
        """Create and register a controller; nothing changes if anything is invalid.

        Raises:
            InvalidValue: unknown kind, bad id, bad clock, config key the kind rejects.
            Conflict: the id is taken.
        """
        cls = kind_class(kind)
        if id is None:
            id = self._new_id(kind)
        elif not _ID.match(id):
            raise InvalidValue(
                f"controller id {id!r} must be 1-64 letters, digits, '_', '.', '-'", field="id")
        if id in self._handles:
            raise Conflict(f"a controller {id!r} already exists", controller=id)
        if len(self._handles) >= self.max_controllers:
            raise Conflict(f"{len(self._handles)} controllers exist, the most allowed "
                           "(setting max_controllers): delete one first",
                           limit=self.max_controllers)
        controller = cls(id, dict(config or {}), log_capacity=self.log_capacity)
        new_clock = make_clock(clock, controller.env, factor, paused, log=controller.log,
                               reaction_s=reaction_s)
        if isinstance(new_clock, HostPacedClock):
            for name in holders or ():
                new_clock.hold(name)
        elif holders:
            raise InvalidValue("holders need a host-paced clock", field="holders")
        handle = ControllerHandle(id, kind, controller, new_clock)
        self._handles[id] = handle
        if self._started:
            handle.ensure_running()
        return handle

    async def remove(self, id: str) -> None:
        """Stop and forget controller ``id``; raises :class:`NotFound`."""
        handle = self.get(id)
        del self._handles[id]
        await handle.close()

    async def start(self) -> None:
        """Start every realtime clock (called from the app's lifespan)."""
        self._started = True
        for handle in self:
            handle.ensure_running()

    async def close(self) -> None:
        """Stop every clock."""
        self._started = False
        for handle in self:
            await handle.close()


__all__ = ["REALTIME_REPLY_CAP_S", "RUN_UNTIL_WALL_CAP_S", "TERMINAL_WAIT_S", "ControllerHandle",
           "LiveHandle", "Registry"]
