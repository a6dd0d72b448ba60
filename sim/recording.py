"""A controller's own recording, in one shape for every kind: what the REST recording
resources (``GET /controllers/{id}/gather`` for a Turbo PMAC's data gathering, ``.../scope``
for a Trio's SCOPE) and the dashboard read.

``columns[i]`` holds the values of source ``names[i]``, one per sample, oldest first;
``cycles[j]`` is the servo cycle sample ``j`` was taken on, so its simulated instant is
exactly ``cycles[j] * servo_period_s``. A PMAC value is the gathered word as a signed integer
of its width (a ``$C`` source: the 48-bit float's value); a Trio value is the TABLE entry.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from .events import wire_time


@dataclass(frozen=True, slots=True)
class Recording:
    """The samples a controller holds (module docstring)."""

    kind: str  # "gather" (PMAC) or "scope" (Trio)
    names: tuple[str, ...]
    sources: tuple[dict[str, Any], ...]  # per source: what it reads (address, TABLE start)
    cycles: tuple[int, ...]
    columns: tuple[tuple[float, ...], ...]
    period_cycles: int
    servo_period_s: float
    running: bool
    wrapped: bool
    capacity: int

    def times(self) -> list[float]:
        """Each sample's simulated instant (cycle × servo period, as the core schedules it),
        in the wire form of every API time (:func:`~.events.wire_time`)."""
        p = self.servo_period_s
        return [wire_time(k * p) for k in self.cycles]


__all__ = ["Recording"]
