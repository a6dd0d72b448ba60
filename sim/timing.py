"""Servo-cycle quantisation.

Both controllers act on a fixed servo interrupt: moves start and end on servo cycles, PMAC
move planning happens on real-time interrupts every I8+1 servo cycles. Quantised instants are
always computed from an integer cycle index (``k * period_s``), never by accumulating
``t += dt``, so two runs of the same inputs produce byte-identical timestamps.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

#: Tolerance, in cycles, for treating a float time as lying exactly on a cycle boundary.
EPS_CYCLES = 1e-6


@dataclass(frozen=True, slots=True)
class ServoClock:
    """A servo interrupt of fixed period.

    Args:
        period_s: servo period in seconds (PMAC: I10 / 2**23 ms; Trio: SERVO_PERIOD µs).
    """

    period_s: float

    def __post_init__(self) -> None:
        if not (self.period_s > 0 and math.isfinite(self.period_s)):
            raise ValueError(f"servo period must be positive and finite, got {self.period_s!r}")

    @property
    def hz(self) -> float:
        return 1.0 / self.period_s

    def t(self, k: int) -> float:
        """Simulated time of servo cycle ``k`` (cycle 0 is t = 0)."""
        return k * self.period_s

    def index(self, t: float) -> int:
        """The last servo cycle at or before ``t``."""
        return math.floor(t / self.period_s + EPS_CYCLES)

    def at_or_after(self, t: float) -> int:
        """The first servo cycle at or after ``t``."""
        return math.ceil(t / self.period_s - EPS_CYCLES)

    def after(self, t: float) -> int:
        """The first servo cycle strictly after ``t``."""
        return self.index(t) + 1

    def cycles(self, duration_s: float) -> int:
        """A duration rounded up to whole servo cycles (a move never ends between cycles)."""
        return max(0, math.ceil(duration_s / self.period_s - EPS_CYCLES))


def pmac_servo_period_s(i10: int) -> float:
    """Turbo PMAC servo period from I10, which is in units of 2**-23 ms (3 713 707 -> 442.7 µs)."""
    return i10 / 8_388_608 / 1000.0


__all__ = ["EPS_CYCLES", "ServoClock", "pmac_servo_period_s"]
