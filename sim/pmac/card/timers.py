"""The coordinate systems' countdown timers Isx11 and Isx12 (TSRM p176; spec §12.3).

Each coordinate system x has two user timers, Isx11 = I(5000 + 100·x + 11) and Isx12: a
signed 24-bit register in servo cycles that the card decrements by one every servo cycle
while CS x is activated by I68 (CSs 1..I68+1). It may be written at any time and counts
down from the written value; it goes on below zero and stops at -8,388,608 (no roll-over).

Nothing runs per servo cycle here: a write remembers the servo cycle it happened on, and a
read computes ``written - cycles elapsed`` ``[INF]`` (spec §12.3 allows the lazy form).
Each write is a ``timer`` event (``var`` "I5111", ``value`` in servo cycles), so a wait's
start is on the event log.
The written value is rounded to an integer (a 24-bit register) ``[INF]``; so the idiom
``I5111=100*8388608/I10`` + ``WHILE (I5111>0) ENDWHILE`` waits ceil(100 ms / servo period)
cycles.
"""

from __future__ import annotations

import math
from collections.abc import Callable

#: The lowest value a timer counts down to (TSRM p176).
FLOOR = -8_388_608
CEILING = 8_388_607

#: Every Isx11 / Isx12 number of CS 1..16.
TIMER_NUMBERS = frozenset(5000 + 100 * cs + nn for cs in range(1, 17) for nn in (11, 12))


def timer_cs(n: int) -> int:
    """The coordinate system whose timer I{n} is (I5111 -> 1, I6612 -> 16)."""
    return (n - 5000) // 100


class CountdownTimers:
    """Write instants of the Isx11/Isx12 timers.

    Args:
        servo_cycle: the current servo-cycle index of the controller's clock.
        on_write: called ``(n, value)`` after each write (the controller's ``timer`` event).
    """

    def __init__(self, servo_cycle: Callable[[], int],
                 on_write: Callable[[int, float], None] | None = None) -> None:
        self._servo_cycle = servo_cycle
        self._on_write = on_write
        self._written: dict[int, tuple[int, int]] = {}  # n -> (value, cycle)

    def clear(self) -> None:
        self._written.clear()

    def write(self, n: int, value: float) -> float:
        """I{n}=value: remember it with the current cycle; the stored (integer) value."""
        v = int(max(FLOOR, min(CEILING, math.floor(value + 0.5))))
        self._written[n] = (v, self._servo_cycle())
        if self._on_write is not None:
            self._on_write(n, float(v))
        return float(v)

    def read(self, n: int, active: bool) -> float | None:
        """Timer I{n} now; None if it was never written (the stored default applies).

        ``active``: CS of the timer is activated by I68 (else it holds its value).
        """
        w = self._written.get(n)
        if w is None:
            return None
        value, at = w
        if not active:
            return float(value)
        return float(max(FLOOR, value - (self._servo_cycle() - at)))


__all__ = ["CEILING", "FLOOR", "TIMER_NUMBERS", "CountdownTimers", "timer_cs"]
