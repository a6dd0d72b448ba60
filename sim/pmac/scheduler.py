"""Turbo PMAC task timing: servo interrupt, real-time interrupt (RTI), background cycle.

The controller's tasks, highest priority first (TUM p236-237, spec §4.1, §9.3):

* **servo interrupt** every servo period, I10 × 2**-23 ms (3 713 707 → 442.7 µs ≈ 2.26 kHz;
  ``servo_hz`` in the config overrides it). Moves start and end on servo cycles.
* **RTI** every I8+1 servo cycles (default I8 = 2 → every 3rd cycle, ≈ 1.33 ms): motion-program
  move planning for each CS that asked for it, then PLC 0. A CS asks for planning when a move
  starts executing; the planning is done at the next RTI.
* **background cycle**: host-command processing, PLC 1-31, housekeeping — whatever time is
  left. :class:`BackgroundCycle` answers the host-command queue, one command line per cycle.

Nothing here runs once per servo cycle: :meth:`Scheduler.call_at` schedules one SimPy timeout
to the instant where something happens (the next RTI, a move's end), computed from integer
cycle indices.

The controller's background loop is :class:`sim.pmac.cpu.Processor` (issue 4): PLC 0 at
every RTI, one background PLC scan and one host command per background cycle, each charged
processor time, and the watchdog (:mod:`sim.pmac.watchdog`). :class:`BackgroundCycle` below is
the plain loop it replaced (one host command per ``cycle_cycles`` servo cycles), kept for
callers that want a card with no processor model. The coordinate systems' move planning keys
off :meth:`Scheduler.next_rti_after` instants.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable, Generator
from heapq import heappush
from typing import Any

import simpy
from simpy.events import NORMAL

from sim.timing import ServoClock

Callback = Callable[[Any], None]


class Wake(simpy.events.Event):
    """An already-triggered event processed at the absolute instant ``t``, calling ``fn``.

    Like ``env.timeout(t - now)`` but cheaper and exact: it goes on the environment's queue
    at ``t`` itself, so quantised instants (``k * period``) are not disturbed by
    ``now + (t - now)`` rounding. Uses SimPy 4's queue layout (``_queue``, ``_eid``), the
    same thing ``Environment.schedule`` does.
    """

    # Triggered and successful from birth (class-level, saving two stores per wake-up).
    _value = None
    _ok = True

    def __init__(self, env: simpy.Environment, t: float, fn: Callback) -> None:
        self.env = env
        self.callbacks = [fn]
        heappush(env._queue, (t, NORMAL, next(env._eid), self))  # type: ignore[attr-defined]


class Scheduler:
    """Servo and RTI instants of one controller.

    Args:
        env: the controller's environment.
        period_s: servo period in seconds.
        rti_cycles: returns I8+1 (read each time, I8 may change).
    """

    def __init__(self, env: simpy.Environment, period_s: float, rti_cycles: Callable[[], int]):
        self.env = env
        self.clock = ServoClock(period_s)
        self._period = period_s
        self._rti_cycles = rti_cycles

    @property
    def period_s(self) -> float:
        return self.clock.period_s

    def rti_period_s(self) -> float:
        return self.clock.t(self._rti_cycles())

    def next_rti_after(self, t: float) -> float:
        """The first RTI strictly after ``t`` (RTIs fall on cycles divisible by I8+1)."""
        m = self._rti_cycles()
        k = math.floor(t / self._period + 1e-6) + 1
        k = -(-k // m) * m
        return k * self._period

    def servo_at_or_after(self, t: float) -> float:
        """``t`` rounded up to a servo cycle."""
        return math.ceil(t / self._period - 1e-6) * self._period

    def call_at(self, t: float, fn: Callback) -> None:
        """Call ``fn(event)`` at simulated time ``t`` (now if ``t`` is past)."""
        env = self.env
        now = env._now  # type: ignore[attr-defined]
        Wake(env, t if t > now else now, fn)


class BackgroundCycle:
    """The background task loop: services queued host commands, one per cycle.

    A command line received at ``t`` is executed at the end of the first background cycle
    that ends strictly after ``t``; cycles are ``cycle_cycles()`` servo cycles long and end on
    servo cycles (light load: 1 cycle, so the reply comes one servo period after the command
    at most ``[INF]``). Later queued commands take one cycle each.
    """

    def __init__(self, scheduler: Scheduler, cycle_cycles: int = 1) -> None:
        self.scheduler = scheduler
        self.env = scheduler.env
        self._cycle_cycles = max(1, int(cycle_cycles))
        self.queue: deque[Callable[[], None]] = deque()
        self._wake: simpy.Event | None = None
        self.cycles = 0
        self.process = self.env.process(self._loop())

    def cycle_cycles(self) -> int:
        """Length of the next background cycle in servo cycles (issue 4 overrides this)."""
        return self._cycle_cycles

    def submit(self, job: Callable[[], None]) -> None:
        """Queue a host command (a callable executed inside a background cycle)."""
        self.queue.append(job)
        if self._wake is not None and not self._wake.triggered:
            self._wake.succeed()

    def run_cycle(self) -> None:
        """What one background cycle does: here, answer one queued host command."""
        if self.queue:
            self.queue.popleft()()

    def _loop(self) -> Generator[simpy.Event, Any, None]:
        env = self.env
        clock = self.scheduler.clock
        while True:
            if not self.queue:
                self._wake = env.event()
                yield self._wake
                self._wake = None
            k = clock.after(env.now) + self.cycle_cycles() - 1
            t = clock.t(k)
            yield env.timeout(max(0.0, t - env.now))
            self.cycles += 1
            self.run_cycle()


__all__ = ["BackgroundCycle", "Scheduler"]
