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


def next_period(c: TrioController) -> None:
    """Run to the middle of the next servo period: a move issued before it has left the
    process buffer (M206-320: transferred at the next servo interrupt)."""
    p = c.clock.period_s
    run_to(c, (c.clock.index(c.env.now) + 1.5) * p)


def moves(c: TrioController, axis: int, n: int, args: list[float], **kw) -> list[str]:
    """Issue ``n`` moves on ``axis``, one per servo period (each transits the process buffer)."""
    out = []
    for _ in range(n):
        out.append(c.move(axis, "MOVE", args, **kw))
        next_period(c)
    return out
