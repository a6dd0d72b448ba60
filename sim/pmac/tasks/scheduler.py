"""Turbo PMAC task timing: the servo interrupt and real-time interrupt (RTI) instants.

The controller's tasks, highest priority first (TUM p236-237, spec §4.1, §9.3):

* **servo interrupt** every servo period, I10 × 2**-23 ms (3 713 707 → 442.7 µs ≈ 2.26 kHz;
  ``servo_hz`` in the config overrides it). Moves start and end on servo cycles.
* **RTI** every I8+1 servo cycles (default I8 = 2 → every 3rd cycle, ≈ 1.33 ms): motion-program
  move planning for each CS that asked for it, then PLC 0. A CS asks for planning when a move
  starts executing; the planning is done at the next RTI (:meth:`Scheduler.next_rti_after`).
* **background**: host-command processing, PLC 1-31, housekeeping — whatever time is left;
  modelled with its processor-time budget by :class:`motionsim.sim.pmac.tasks.cpu.Processor` (issue
  4),
  with the watchdog in :mod:`motionsim.sim.pmac.tasks.watchdog`.

Nothing here runs once per servo cycle: a :class:`Wake` puts one already-triggered event on the
SimPy queue at the instant where something happens (the next RTI, a move's end), computed from
integer cycle indices.
"""

from __future__ import annotations

from collections.abc import Callable
from heapq import heappush
from typing import Any

import simpy
from motionsim.sim.timing import ServoClock
from simpy.events import NORMAL

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


def wake_at(env: simpy.Environment, t: float, fn: Callback, old: Wake | None = None) -> Wake:
    """Call ``fn(event)`` at the absolute instant ``t``: a :class:`Wake`.

    ``old`` is a wake-up of the caller's that may be re-used: once SimPy has processed it
    (``callbacks is None``) nothing else refers to it, so it is put on the queue again instead
    of allocating a new event — one allocation less per move on the streaming path. Cancelled
    wake-ups (callbacks emptied, still queued) are never re-used. The queue entry is the same
    as a new Wake's (same ``eid`` order), so the schedule is unchanged.
    """
    if old is not None and old.callbacks is None:
        old.callbacks = [fn]
        heappush(env._queue, (t, NORMAL, next(env._eid), old))  # type: ignore[attr-defined]
        return old
    return Wake(env, t, fn)


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
        self._rti_cycles = rti_cycles

    @property
    def period_s(self) -> float:
        return self.clock.period_s

    def rti_period_s(self) -> float:
        return self.clock.t(self._rti_cycles())

    def next_rti_after(self, t: float) -> float:
        """The first RTI strictly after ``t`` (RTIs fall on cycles divisible by I8+1)."""
        m = self._rti_cycles()
        k = self.clock.after(t)
        return self.clock.t(-(-k // m) * m)

    def rti_at_or_after(self, t: float) -> float:
        """The first RTI at or after ``t`` (on a servo cycle divisible by I8+1)."""
        m = self._rti_cycles()
        k = self.clock.at_or_after(t)
        return self.clock.t(-(-k // m) * m)

    def servo_at_or_after(self, t: float) -> float:
        """``t`` rounded up to a servo cycle."""
        clock = self.clock
        return clock.t(clock.at_or_after(t))


__all__ = ["Scheduler", "Wake", "wake_at"]
