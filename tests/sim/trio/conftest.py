"""Helpers for the Trio tests: a controller with TN20-friendly axis settings, run in virtual time.

Profiles used throughout: SPEED 1000, ACCEL = DECEL = 100 000 units/s², so a move of L units
(L >= 10) takes 0.02 + (L - 10) / 1000 s: 10 units -> 20 servo periods, 200 units -> 210.
"""

from __future__ import annotations

import pytest
from motionsim.sim.trio import TrioController

FAST = {"speed": 1000.0, "accel": 100_000.0, "decel": 100_000.0}


def make(**config) -> TrioController:
    return TrioController("trio", {**FAST, **config})


@pytest.fixture
def trio() -> TrioController:
    return make()


def run_to(c: TrioController, t: float) -> None:
    """Advance the simulation to simulated time ``t``."""
    c.env.run(until=t)


def cycle(c: TrioController, t: float) -> int:
    """The servo period index of an event time (exact for servo instants)."""
    k = round(t / c.clock.period_s)
    assert abs(k * c.clock.period_s - t) < 1e-12, f"{t} is not on a servo period"
    return k


def fields(c: TrioController, type_: str, **match) -> list[tuple[float, dict]]:
    """``(t, fields)`` of every event of ``type_`` whose fields include ``match``."""
    return [
        (e.t, dict(e.fields))
        for e in c.log.events(type_)
        if all(e.fields.get(k) == v for k, v in match.items())
    ]
