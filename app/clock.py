"""Clock drivers: who moves a controller's simulated time, and how fast.

A controller's ``simpy.Environment`` never moves on its own. One clock per controller steps it:

- :class:`VirtualClock` — time moves only when asked (``advance``, ``run_until``,
  ``run_until_idle``, or a terminal command waiting for its reply) and as fast as the CPU
  allows. Tests and scenarios use it; runs are deterministic.
- :class:`RealtimeClock` — one asyncio task keeps simulated time equal to wall time × ``factor``
  (1 = real time, 10 = ten times faster). It sleeps until the wall instant of the next
  scheduled SimPy event (``env.peek()``), and is woken early when a command changes the
  schedule. Commands are applied between steps on the same event loop: no threads, no locks,
  no ``time.sleep`` and no ``simpy.rt``.

Both share :meth:`Clock.sync` (bring ``env`` to "now" before a command is applied — a no-op for
a virtual clock) and :meth:`Clock.wake` (the schedule may have changed — a no-op for a virtual
clock), which is all :class:`motionsim.app.registry.ControllerHandle` needs.

Events exactly at a target instant are processed: advancing by 1 s from t = 0 runs everything
scheduled at t <= 1 s, and leaves ``env.now`` at 1 s even when nothing was scheduled there.
"Exactly" allows 1 ns of float rounding (``3 * 0.1`` is 0.30000000000000004): an event that
close after the target is processed too, and ``env.now`` is then its time.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import math
import time
from collections import deque
from collections.abc import Callable, Mapping
from typing import Any, Literal

import simpy
from motionsim.sim.controller import Reply
from motionsim.sim.errors import Conflict, InvalidValue
from motionsim.sim.events import Event, EventLog

log = logging.getLogger("motionsim.clock")

ClockMode = Literal["virtual", "realtime"]

_INF = float("inf")

#: Float rounding tolerated when deciding whether an event is due at a target instant.
_TIME_EPS_S = 1e-9


def _check_seconds(value: float, field: str) -> float:
    """A duration in seconds must be finite and not negative (422 ``validation_error``)."""
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise InvalidValue(f"{field} must be a number of seconds, got {value!r}",
                           field=field) from None
    if not math.isfinite(value) or value < 0:
        raise InvalidValue(f"{field} must be finite and >= 0, got {value!r}", field=field)
    return value


def _check_factor(value: float) -> float:
    """A speed-up factor must be finite and > 0."""
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise InvalidValue(f"factor must be a number, got {value!r}", field="factor") from None
    if not math.isfinite(value) or value <= 0:
        raise InvalidValue(f"factor must be finite and > 0, got {value!r}", field="factor")
    return value


def run_env_to(env: simpy.Environment, target: float, max_steps: int | None = None) -> bool:
    """Process every event scheduled at or before ``target``, then set ``env.now`` to it.

    Returns False when ``max_steps`` events were processed and more are due (the caller
    yields to the event loop and calls again); True when ``env.now == target`` (or later).
    """
    steps = 0
    limit = target + max(_TIME_EPS_S, abs(target) * 1e-12)
    while env.peek() <= limit:
        if max_steps is not None and steps >= max_steps:
            return False
        env.step()
        steps += 1
    if target > env.now:
        env.run(until=target)
        if env.peek() <= env.now:
            # SimPy >= 4.1 re-schedules the spent ``until`` event (no callbacks left) at the
            # stop instant; every real event up to ``target`` was processed above, so this is
            # it: consume it, or ``peek()`` would report a due event forever.
            env.step()
    return True


class Clock:
    """What every clock offers to the handle and the REST ``/clock`` resource."""

    mode: ClockMode

    def __init__(self, env: simpy.Environment, factor: float = 1.0, paused: bool = False):
        self.env = env
        self.factor = _check_factor(factor)
        self.paused = bool(paused)

    @property
    def t(self) -> float:
        """The current simulated time in seconds."""
        return self.env.now

    def sync(self) -> None:
        """Bring ``env`` to the current instant before a command is applied."""

    def wake(self) -> None:
        """The schedule may have changed (a command was applied): re-plan the next step."""

    def set(self, *, factor: float | None = None, paused: bool | None = None) -> None:
        """Change the speed-up factor and/or pause / resume."""
        if factor is not None:
            self.factor = _check_factor(factor)
        if paused is not None:
            self.paused = bool(paused)

    def start(self) -> None:
        """Start driving time (needs a running asyncio loop for a realtime clock)."""

    async def stop(self) -> None:
        """Stop driving time (the environment keeps its state)."""

    def to_dict(self) -> dict[str, Any]:
        """The API's ``Clock``: ``{"mode", "factor", "paused", "t"}``."""
        return {"mode": self.mode, "factor": self.factor, "paused": self.paused, "t": self.t}


class VirtualClock(Clock):
    """Simulated time moves only when asked, as fast as the CPU allows.

    ``factor`` is kept (so a clock switched to realtime remembers it) but has no effect;
    a paused virtual clock refuses to advance (409 ``conflict``).
    """

    mode: ClockMode = "virtual"

    def _check_running(self) -> None:
        if self.paused:
            raise Conflict("the clock is paused; PATCH it with paused=false first")

    def advance(self, seconds: float) -> None:
        """Run the simulation forward by ``seconds`` (0 is a no-op)."""
        seconds = _check_seconds(seconds, "seconds")
        self._check_running()
        if seconds == 0:
            return
        run_env_to(self.env, self.env.now + seconds)

    def run_until(
        self,
        log: EventLog,
        pattern: Mapping[str, Any] | Callable[[Event], bool],
        timeout_s: float,
        *,
        wall_budget_s: float | None = 30.0,
    ) -> Event | None:
        """Run until the first *new* event matching ``pattern`` is emitted, at most ``timeout_s``.

        ``pattern`` is ``{"type": ..., field: value, ...}`` (see :meth:`Event.matches`) or a
        predicate. On a match the clock stops at the event's instant (events at that same instant
        emitted after it are still to be processed); otherwise it ends at ``now + timeout_s``.
        ``wall_budget_s`` bounds the wall time spent (a simulation with an event per servo cycle
        asked to run for days); when exceeded it returns ``None`` with the clock where it got to.
        """
        timeout_s = _check_seconds(timeout_s, "timeout_s")
        self._check_running()
        match = pattern if callable(pattern) else (lambda e, p=dict(pattern): e.matches(p))
        found: list[Event] = []

        def listener(event: Event) -> None:
            if not found and match(event):
                found.append(event)

        env = self.env
        deadline = env.now + timeout_s
        unlisten = log.listen(listener)
        try:
            t_wall_end = None if wall_budget_s is None else time.monotonic() + wall_budget_s
            steps = 0
            limit = deadline + _TIME_EPS_S
            while not found and env.peek() <= limit:
                env.step()
                steps += 1
                if t_wall_end is not None and steps % 4096 == 0 and time.monotonic() > t_wall_end:
                    return None
        finally:
            unlisten()
        if found:
            return found[0]
        run_env_to(env, deadline)
        return None

    def run_until_idle(self, max_s: float | None = None, max_steps: int = 10_000_000) -> bool:
        """Run until nothing is scheduled (True), or ``max_s`` / ``max_steps`` are used up.

        Controllers with a perpetual servo process are never idle; bound the call with ``max_s``.
        """
        self._check_running()
        env = self.env
        deadline = _INF if max_s is None else env.now + _check_seconds(max_s, "max_s")
        steps = 0
        while env.peek() <= deadline:
            if env.peek() == _INF:
                break
            if steps >= max_steps:
                return False
            env.step()
            steps += 1
        if env.peek() == _INF:
            return True
        if deadline != _INF:
            run_env_to(env, deadline)
        return False

    def run_until_reply(self, reply: Reply, max_s: float) -> None:
        """Step until ``reply`` is done, at most ``max_s`` of simulated time.

        Done: the clock stops at the reply's instant. Not done: the clock is at ``now + max_s``
        and the reply stays pending (it later shows as a ``terminal_reply`` event).
        """
        env = self.env
        deadline = env.now + max_s
        while not reply.done and env.peek() <= deadline + _TIME_EPS_S:
            env.step()
        if not reply.done:
            run_env_to(env, deadline)


class RealtimeClock(Clock):
    """Simulated time = wall time × ``factor``, driven by one asyncio task.

    ``t`` is computed from the wall clock whenever it is asked, so it advances even when no
    SimPy event is scheduled; :meth:`sync` runs ``env`` to that instant before each command is
    applied, so commands land at the simulated time matching their arrival.

    The task awaits the wall instant of ``env.peek()`` (a ``loop.call_later`` timer on a
    future, no polling) and is woken early by :meth:`wake`. When the CPU cannot keep up the
    task steps what is due in slices of ``slice_steps`` events, yielding to the loop in
    between, so HTTP requests and WebSocket subscribers keep being served.

    ``lateness_s`` holds the most recent wake-up latenesses (wall seconds between the instant
    an event was due and the instant the task processed it) for the bench.
    """

    mode: ClockMode = "realtime"

    def __init__(
        self,
        env: simpy.Environment,
        factor: float = 1.0,
        paused: bool = False,
        *,
        slice_steps: int = 2000,
        lateness_window: int = 10_000,
    ) -> None:
        super().__init__(env, factor, paused)
        self.slice_steps = slice_steps
        self._anchor_wall = time.monotonic()
        self._anchor_sim = env.now
        self._task: asyncio.Task[None] | None = None
        self._waiter: asyncio.Future[None] | None = None
        self.lateness_s: deque[float] = deque(maxlen=lateness_window)
        self.last_error: BaseException | None = None

    # -- time ------------------------------------------------------------------------------

    @property
    def t(self) -> float:
        if self.paused:
            return max(self.env.now, self._anchor_sim)
        wall = time.monotonic() - self._anchor_wall
        return max(self.env.now, self._anchor_sim + wall * self.factor)

    def _wall_of(self, t_sim: float) -> float:
        """The monotonic wall instant at which simulated time ``t_sim`` is reached."""
        return self._anchor_wall + (t_sim - self._anchor_sim) / self.factor

    def _reanchor(self) -> None:
        self._anchor_sim = self.env.now
        self._anchor_wall = time.monotonic()

    def sync(self) -> None:
        run_env_to(self.env, self.t)

    def set(self, *, factor: float | None = None, paused: bool | None = None) -> None:
        new_factor = None if factor is None else _check_factor(factor)
        if not self.paused:
            self.sync()
        if new_factor is not None:
            self.factor = new_factor
        if paused is not None:
            self.paused = bool(paused)
        self._reanchor()
        self.wake()

    # -- the driving task ------------------------------------------------------------------

    @property
    def running(self) -> bool:
        return self._task is not None and not self._task.done()

    def start(self) -> None:
        if self.running:
            return
        self._task = asyncio.get_running_loop().create_task(
            self._drive(), name=f"realtime-clock-{id(self.env):x}"
        )

    async def stop(self) -> None:
        task, self._task = self._task, None
        if task is None:
            return
        task.cancel()
        with contextlib.suppress(asyncio.CancelledError):
            await task

    def wake(self) -> None:
        waiter = self._waiter
        if waiter is not None and not waiter.done():
            waiter.set_result(None)

    def _on_timer(self, waiter: asyncio.Future[None]) -> None:
        if not waiter.done():
            waiter.set_result(None)

    async def _drive(self) -> None:
        loop = asyncio.get_running_loop()
        env = self.env
        while True:
            behind = False
            try:
                behind = not run_env_to(env, self.t, self.slice_steps)
            except Exception as exc:  # a failed SimPy process: report it, keep time going
                self.last_error = exc
                log.exception("simulation error in realtime clock")
            if behind:
                await asyncio.sleep(0)
                continue
            waiter: asyncio.Future[None] = loop.create_future()
            self._waiter = waiter
            nxt = env.peek()
            timer = None
            due_wall = None
            if not self.paused and nxt != _INF:
                due_wall = self._wall_of(nxt)
                timer = loop.call_later(max(0.0, due_wall - time.monotonic()),
                                        self._on_timer, waiter)
            try:
                await waiter
            finally:
                self._waiter = None
                if timer is not None:
                    timer.cancel()
            if due_wall is not None:
                late = time.monotonic() - due_wall
                if late >= 0:
                    self.lateness_s.append(late)


def make_clock(
    mode: ClockMode, env: simpy.Environment, factor: float = 1.0, paused: bool = False
) -> VirtualClock | RealtimeClock:
    """The clock of ``mode`` for ``env``."""
    if mode == "virtual":
        return VirtualClock(env, factor, paused)
    if mode == "realtime":
        return RealtimeClock(env, factor, paused)
    raise InvalidValue(f"clock mode must be 'virtual' or 'realtime', got {mode!r}", field="mode")


__all__ = ["Clock", "ClockMode", "RealtimeClock", "VirtualClock", "make_clock", "run_env_to"]
