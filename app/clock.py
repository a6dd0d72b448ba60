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

No clock ever runs the simulation for long without yielding: work is done in **slices** of
``SLICE_S`` wall seconds (:func:`run_env_to` with ``wall_end``; a virtual clock's slice also
does ``SLICE_S`` of CPU work, :func:`_cpu_end`, so that a slice the OS pre-empted is not cut
short), and the ``async`` ways
in (:meth:`VirtualClock.advance_async`, :meth:`VirtualClock.run_until_async`,
:meth:`VirtualClock.run_until_reply_async`, the realtime task) give the event loop back between
slices, so ``/health``, other controllers and other clients are served while one controller
computes. Slicing is invisible in the event log: the same events are processed in the same
order whatever the slice boundaries (tests compare logs). A realtime clock that cannot keep up
reports ``lag_s`` and a ``clock_lag`` event, and slips (gives up simulated time) instead of
freezing the loop to catch up.

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
from collections.abc import Callable, Generator, Mapping
from typing import Any, Literal, TypeVar

import simpy

from ..sim.controller import Reply
from ..sim.errors import Conflict, InvalidValue
from ..sim.events import Event, EventLog, wire_time
from ..sim.simpy_adapter import nothing_due_by, step_due

log = logging.getLogger("motionsim.clock")

T = TypeVar("T")

ClockMode = Literal["virtual", "realtime", "host-paced"]

_INF = float("inf")

#: Float rounding tolerated when deciding whether an event is due at a target instant.
_TIME_EPS_S = 1e-9

#: Wall seconds one slice of simulation may take before the event loop gets a turn.
SLICE_S = 0.004

#: Event-loop iterations given to everything else between two slices: serving one HTTP request
#: takes several (read, parse, route, write), each iteration is microseconds when idle.
LOOP_TURNS = 16

#: SimPy steps between two looks at the wall clock in a slice (a look costs ~5 % of a step).
_WALL_CHECK_STEPS = 4

#: Wall seconds a ``run_until`` may take at most by default (an event that never comes).
RUN_UNTIL_WALL_S = 30.0


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


def drain(steps: Generator[None, None, T]) -> T:
    """Run a sliced computation to its end without yielding (sync callers: scenarios, replay)."""
    while True:
        try:
            next(steps)
        except StopIteration as stop:
            return stop.value


async def drain_async(steps: Generator[None, None, T], started: bool = False) -> T:
    """Run a sliced computation, giving the event loop a turn between slices (``started``:
    its first slice has run already, the loop's turn comes first).

    Cancelling the awaiting task (a client that went away) stops it at a slice boundary: the
    environment is consistent there, the clock stays where it got to.
    """
    try:
        if started:
            await loop_turns()
        while True:
            try:
                next(steps)
            except StopIteration as stop:
                return stop.value
            await loop_turns()
    finally:
        steps.close()


async def loop_turns(n: int = LOOP_TURNS) -> None:
    """Give the event loop ``n`` iterations (I/O polled in each) before the next slice."""
    for _ in range(n):
        await asyncio.sleep(0)


def reply_steps(env: simpy.Environment, reply: Reply, max_s: float,
                slice_s: float = SLICE_S) -> Generator[None, None, None]:
    """Step until ``reply`` is done, at most ``max_s`` simulated seconds, yielding between
    slices; not done by then: ``env.now`` is ``now + max_s`` and the reply stays pending."""
    deadline = env.now + max_s
    limit = _limit(deadline)
    while True:
        slice_end, cpu_end = _wall_end(slice_s), _cpu_end(slice_s)
        steps = 0
        while not reply.done and env.peek() <= limit:
            env.step()
            steps += 1
            if (steps % _WALL_CHECK_STEPS == 0 and time.monotonic() > slice_end
                    and time.thread_time() > cpu_end):
                break
        if reply.done or env.peek() > limit:
            break
        yield
    if not reply.done:
        run_env_to(env, deadline)


def _check_factor(value: float) -> float:
    """A speed-up factor must be finite and > 0."""
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise InvalidValue(f"factor must be a number, got {value!r}", field="factor") from None
    if not math.isfinite(value) or value <= 0:
        raise InvalidValue(f"factor must be finite and > 0, got {value!r}", field="factor")
    return value


def _limit(target: float) -> float:
    """``target`` plus the float rounding tolerated at it."""
    return target + max(_TIME_EPS_S, abs(target) * 1e-12)


def _wall_end(slice_s: float = SLICE_S) -> float:
    return time.monotonic() + slice_s


def _cpu_end(slice_s: float = SLICE_S) -> float:
    """The event-loop thread's CPU time at which a virtual clock's slice has done its share.

    A virtual clock's slice ends once both ``slice_s`` of wall time and ``slice_s`` of this
    thread's CPU time have passed: a slice the OS pre-empted (a loaded machine) still does
    its share of the simulation before the loop's turn, instead of ending at once when it
    is resumed. So controllers advancing side by side each get the same share of the
    service, whatever the machine does meanwhile (issue 35: 100 controllers streaming at
    once, the slowest within 20 % of the fastest). The CPU clock is read only once the wall
    budget is spent."""
    return time.thread_time() + slice_s


def run_env_to(env: simpy.Environment, target: float, max_steps: int | None = None,
               wall_end: float | None = None, cpu_end: float | None = None) -> bool:
    """Process every event scheduled at or before ``target``, then set ``env.now`` to it.

    Returns False when ``max_steps`` events were processed, or the monotonic instant
    ``wall_end`` passed (and, if given, the thread CPU time ``cpu_end``: see
    :func:`_cpu_end`), and more are due (the caller yields to the event loop and calls
    again); True when ``env.now == target`` (or later).
    """
    steps = 0
    limit = _limit(target)
    while True:
        # the clocks are looked at every _WALL_CHECK_STEPS events (step_due: the steps between)
        n = _WALL_CHECK_STEPS if max_steps is None else min(_WALL_CHECK_STEPS, max_steps - steps)
        done = step_due(env, limit, n)
        steps += done
        if done < n or nothing_due_by(env, limit):
            break  # nothing more due by the target
        if max_steps is not None and steps >= max_steps:
            return False
        if (wall_end is not None and time.monotonic() > wall_end
                and (cpu_end is None or time.thread_time() > cpu_end)):
            return False
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
        """The API's ``Clock``: ``{"mode", "factor", "paused", "t"}`` (+ the mode's own)."""
        return {"mode": self.mode, "factor": self.factor, "paused": self.paused,
                "t": wire_time(self.t)}


class DrivenClock(Clock):
    """A clock that moves time by itself, in one asyncio task of its own (``_drive``)."""

    _task: asyncio.Task[None] | None = None

    async def _drive(self) -> None:
        raise NotImplementedError

    @property
    def running(self) -> bool:
        return self._task is not None and not self._task.done()

    def _start_task(self, name: str) -> None:
        """Start ``_drive`` as the task ``name`` (this environment's), unless it runs."""
        if not self.running:
            self._task = asyncio.get_running_loop().create_task(
                self._drive(), name=f"{name}-{id(self.env):x}")

    async def stop(self) -> None:
        task, self._task = self._task, None
        if task is None:
            return
        task.cancel()
        with contextlib.suppress(asyncio.CancelledError):
            await task


class VirtualClock(Clock):
    """Simulated time moves only when asked, as fast as the CPU allows.

    ``factor`` is kept (so a clock switched to realtime remembers it) but has no effect;
    a paused virtual clock refuses to advance (409 ``conflict``).

    Each way of moving time is a sliced computation (a generator yielding between slices of at
    most ``slice_s`` wall seconds): the plain methods run it through, the ``*_async`` ones give
    the event loop a turn between slices. Both process exactly the same events.
    """

    mode: ClockMode = "virtual"

    def __init__(self, env: simpy.Environment, factor: float = 1.0, paused: bool = False,
                 *, slice_s: float = SLICE_S) -> None:
        super().__init__(env, factor, paused)
        self.slice_s = slice_s

    def _check_running(self) -> None:
        if self.paused:
            raise Conflict("the clock is paused; PATCH it with paused=false first")

    # -- the sliced computations -------------------------------------------------------------

    def advance_steps(self, seconds: float) -> Generator[None, None, None]:
        """Run forward by ``seconds``, yielding between slices (validated before the first)."""
        seconds = _check_seconds(seconds, "seconds")
        self._check_running()
        return self._advance(seconds)

    def _advance(self, seconds: float) -> Generator[None, None, None]:
        if seconds == 0:
            return
        target = self.env.now + seconds
        while not run_env_to(self.env, target, wall_end=_wall_end(self.slice_s),
                             cpu_end=_cpu_end(self.slice_s)):
            yield

    def run_until_steps(
        self,
        log: EventLog,
        pattern: Mapping[str, Any] | Callable[[Event], bool],
        timeout_s: float,
        *,
        wall_budget_s: float | None = RUN_UNTIL_WALL_S,
    ) -> Generator[None, None, Event | None]:
        """:meth:`run_until` as a sliced computation (validated before the first slice)."""
        timeout_s = _check_seconds(timeout_s, "timeout_s")
        self._check_running()
        match = pattern if callable(pattern) else (lambda e, p=dict(pattern): e.matches(p))
        return self._run_until(log, match, timeout_s, wall_budget_s)

    def _run_until(self, log: EventLog, match: Callable[[Event], bool], timeout_s: float,
                   wall_budget_s: float | None) -> Generator[None, None, Event | None]:
        found: list[Event] = []

        def listener(event: Event) -> None:
            if not found and match(event):
                found.append(event)

        env = self.env
        deadline = env.now + timeout_s
        limit = _limit(deadline)
        t_wall_end = None if wall_budget_s is None else time.monotonic() + wall_budget_s
        unlisten = log.listen(listener)
        try:
            while True:
                slice_end, cpu_end = _wall_end(self.slice_s), _cpu_end(self.slice_s)
                steps = 0
                while not found and env.peek() <= limit:
                    env.step()
                    steps += 1
                    if (steps % _WALL_CHECK_STEPS == 0 and time.monotonic() > slice_end
                            and time.thread_time() > cpu_end):
                        break
                if found or env.peek() > limit:
                    break
                if t_wall_end is not None and time.monotonic() > t_wall_end:
                    return None
                yield
        finally:
            unlisten()
        if found:
            return found[0]
        run_env_to(env, deadline)
        return None

    def run_until_reply_steps(self, reply: Reply, max_s: float) -> Generator[None, None, None]:
        """:meth:`run_until_reply` as a sliced computation."""
        return reply_steps(self.env, reply, max_s, self.slice_s)

    # -- run through (sync) and sliced (async) -----------------------------------------------

    def advance(self, seconds: float) -> None:
        """Run the simulation forward by ``seconds`` (0 is a no-op)."""
        drain(self.advance_steps(seconds))

    async def advance_async(self, seconds: float) -> None:
        """:meth:`advance`, yielding to the event loop between slices."""
        await drain_async(self.advance_steps(seconds))

    def run_until(
        self,
        log: EventLog,
        pattern: Mapping[str, Any] | Callable[[Event], bool],
        timeout_s: float,
        *,
        wall_budget_s: float | None = RUN_UNTIL_WALL_S,
    ) -> Event | None:
        """Run until the first *new* event matching ``pattern`` is emitted, at most ``timeout_s``.

        ``pattern`` is ``{"type": ..., field: value, ...}`` (see :meth:`Event.matches`) or a
        predicate. On a match the clock stops at the event's instant (events at that same instant
        emitted after it are still to be processed); otherwise it ends at ``now + timeout_s``.
        ``wall_budget_s`` bounds the wall time spent (a simulation with an event per servo cycle
        asked to run for days); when exceeded it returns ``None`` with the clock where it got to.
        """
        return drain(self.run_until_steps(log, pattern, timeout_s, wall_budget_s=wall_budget_s))

    async def run_until_async(
        self,
        log: EventLog,
        pattern: Mapping[str, Any] | Callable[[Event], bool],
        timeout_s: float,
        *,
        wall_budget_s: float | None = RUN_UNTIL_WALL_S,
    ) -> Event | None:
        """:meth:`run_until`, yielding to the event loop between slices."""
        return await drain_async(
            self.run_until_steps(log, pattern, timeout_s, wall_budget_s=wall_budget_s))

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
        drain(self.run_until_reply_steps(reply, max_s))

    async def run_until_reply_async(self, reply: Reply, max_s: float) -> None:
        """:meth:`run_until_reply`, yielding to the event loop between slices."""
        await drain_async(self.run_until_reply_steps(reply, max_s))


class RealtimeClock(DrivenClock):
    """Simulated time = wall time × ``factor``, driven by one asyncio task.

    The *schedule* (:meth:`target`) is computed from the wall clock whenever it is asked, so it
    advances even when no SimPy event is scheduled; :meth:`sync` runs ``env`` to it before each
    command is applied, so commands land at the simulated time matching their arrival.

    The task awaits the wall instant of ``env.peek()`` (a ``loop.call_later`` timer on a
    future, no polling) and is woken early by :meth:`wake`. When the CPU cannot keep up it
    steps what is due in slices of at most ``slice_s`` wall seconds (and ``slice_steps``
    events), yielding to the loop in between, so HTTP requests and WebSocket subscribers keep
    being served; :meth:`sync` is bounded the same way (a command then lands at the instant the
    simulation has reached).

    Lag: ``lag_s`` is how many wall seconds the simulation is behind its schedule. Above
    ``lag_report_s`` the clock is *behind* (a ``clock_lag`` event with ``behind: true``; one
    with ``behind: false`` when the lag is back under a fifth of it). It never falls more than
    ``max_lag_s`` behind: beyond that it re-anchors the schedule at the simulation's instant,
    giving up the simulated time it could not compute (``slipped_s`` adds it up), so a factor
    the CPU cannot sustain degrades to the speed it can, and nothing waits for a catch-up.

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
        log: EventLog | None = None,
        slice_s: float = SLICE_S,
        slice_steps: int = 2000,
        lag_report_s: float = 0.1,
        max_lag_s: float = 0.5,
        lateness_window: int = 10_000,
    ) -> None:
        super().__init__(env, factor, paused)
        self.log = log
        self.slice_s = slice_s
        self.slice_steps = slice_steps
        self.lag_report_s = lag_report_s
        self.max_lag_s = max_lag_s
        self.behind = False
        self.slipped_s = 0.0
        self._anchor_wall = time.monotonic()
        self._anchor_sim = env.now
        self._waiter: asyncio.Future[None] | None = None
        self.lateness_s: deque[float] = deque(maxlen=lateness_window)
        self.last_error: BaseException | None = None

    # -- time ------------------------------------------------------------------------------

    def target(self) -> float:
        """The simulated instant the schedule says it is now (wall time × factor)."""
        if self.paused:
            return max(self.env.now, self._anchor_sim)
        wall = time.monotonic() - self._anchor_wall
        return max(self.env.now, self._anchor_sim + wall * self.factor)

    @property
    def t(self) -> float:
        """The simulated instant reached: the schedule, or the next due event when behind."""
        return max(self.env.now, min(self.target(), self.env.peek()))

    @property
    def lag_s(self) -> float:
        """Wall seconds the simulation is behind its schedule (0 when keeping up)."""
        return max(0.0, (self.target() - self.t) / self.factor)

    def _wall_of(self, t_sim: float) -> float:
        """The monotonic wall instant at which simulated time ``t_sim`` is reached."""
        return self._anchor_wall + (t_sim - self._anchor_sim) / self.factor

    def _reanchor(self) -> None:
        self._anchor_sim = self.env.now
        self._anchor_wall = time.monotonic()

    def sync(self) -> None:
        """Run to the schedule, at most one slice; when behind the command lands earlier."""
        run_env_to(self.env, self.target(), self.slice_steps, _wall_end(self.slice_s))

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

    def to_dict(self) -> dict[str, Any]:
        out = super().to_dict()
        out["lag_s"] = self.lag_s
        out["behind"] = self.behind
        out["slipped_s"] = self.slipped_s
        return out

    # -- lag -------------------------------------------------------------------------------

    def _check_lag(self) -> None:
        """Report crossing into / out of *behind*; slip beyond ``max_lag_s``."""
        lag = self.lag_s
        if lag > self.max_lag_s:
            ahead = self.target() - self.env.now
            self._anchor_sim = self.env.now + self.max_lag_s * self.factor
            self._anchor_wall = time.monotonic()
            self.slipped_s += max(0.0, ahead - self.max_lag_s * self.factor)
        if not self.behind and lag > self.lag_report_s:
            self.behind = True
            self._report(lag)
            who = f"controller {self.log.controller}" if self.log is not None else "a controller"
            log.warning("%s: realtime clock behind by %.3f s (factor %g)", who, lag,
                        self.factor)
        elif self.behind and lag < self.lag_report_s / 5:
            self.behind = False
            self._report(lag)

    def _report(self, lag: float) -> None:
        if self.log is not None:
            self.log.emit("clock_lag", lag_s=round(lag, 6), behind=self.behind)

    # -- the driving task ------------------------------------------------------------------

    def start(self) -> None:
        self._start_task("realtime-clock")

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
                behind = not run_env_to(env, self.target(), self.slice_steps,
                                        _wall_end(self.slice_s))
            except Exception as exc:  # a failed SimPy process: report it, keep time going
                self.last_error = exc
                log.exception("simulation error in realtime clock")
            self._check_lag()
            if behind:
                await loop_turns()
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
    mode: ClockMode, env: simpy.Environment, factor: float = 1.0, paused: bool = False,
    *, log: EventLog | None = None, reaction_s: float = 0.0,
) -> Clock:
    """The clock of ``mode`` for ``env`` (``log``: where a clock reports, e.g. its lag)."""
    if mode == "virtual":
        return VirtualClock(env, factor, paused)
    if mode == "realtime":
        return RealtimeClock(env, factor, paused, log=log)
    if mode == "host-paced":
        from .host_paced import HostPacedClock

        return HostPacedClock(env, factor, paused, log=log, reaction_s=reaction_s)
    raise InvalidValue(
        f"clock mode must be 'virtual', 'realtime' or 'host-paced', got {mode!r}", field="mode")


__all__ = ["RUN_UNTIL_WALL_S", "SLICE_S", "Clock", "ClockMode", "DrivenClock", "RealtimeClock",
           "VirtualClock", "drain", "drain_async", "make_clock", "reply_steps", "run_env_to"]
