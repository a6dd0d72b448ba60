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

Nothing here runs once per servo cycle: a :class:`~motionsim.sim.simpy_adapter.Wake` puts one
already-triggered event on the SimPy queue at the instant where something happens (the next RTI,
a move's end), computed from integer cycle indices.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import simpy

from ...simpy_adapter import Wake, wake_at
from ...timing import EPS_CYCLES, ServoClock

__all__ = ["Scheduler", "Wake", "first_rti_after", "servo_at_or_after", "wake_at"]

_floor = math.floor
_ceil = math.ceil


def servo_at_or_after(t: float, period_s: float) -> float:
    """``t`` rounded up to a servo cycle (:meth:`ServoClock.at_or_after`, one call): the one
    home of the rounding :meth:`Scheduler.servo_at_or_after` and a blend's hand-off use."""
    return _ceil(t / period_s - EPS_CYCLES) * period_s


def first_rti_after(t: float, period_s: float, rti_cycles: int) -> float:
    """The first RTI strictly after ``t``: the first servo cycle after ``t``
    (:meth:`ServoClock.after`) rounded up to a multiple of ``rti_cycles`` = I8+1 (TUM p236).

    The one home of the rule: :meth:`Scheduler.next_rti_after` and the coordinate system's
    per-line path (with I8+1 cached) both call it."""
    k = _floor(t / period_s + EPS_CYCLES) + 1
    return -(-k // rti_cycles) * rti_cycles * period_s


class Scheduler:
    """Servo and RTI instants of one controller.

    Args:
        env: the controller's environment.
        period_s: servo period in seconds.
        rti_cycles: returns I8+1 (read each time, I8 may change).
    """

    def __init__(
        self, env: simpy.Environment, period_s: float, rti_cycles: Callable[[], int]
    ) -> None:
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
        return first_rti_after(t, self.clock.period_s, self._rti_cycles())

    def rti_at_or_after(self, t: float) -> float:
        """The first RTI at or after ``t`` (on a servo cycle divisible by I8+1)."""
        m = self._rti_cycles()
        k = self.clock.at_or_after(t)
        return self.clock.t(-(-k // m) * m)

    def servo_at_or_after(self, t: float) -> float:
        """``t`` rounded up to a servo cycle."""
        return servo_at_or_after(t, self.clock.period_s)

