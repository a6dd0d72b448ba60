"""The ``A`` (abort) stop of a coordinate system's axes.

What the manuals say: ``A`` breaks into the trajectory at once and each motor decelerates to
a stop at its own abort / limit deceleration rate Ixx15 (counts/ms², TUM p319, PSRM p73), not
along the programmed path. So an axis stops after ``|v| / rate``: a slow axis stops sooner
than a fast one, and where several axes move together the path bends.

Inferences ``[INF]``:

* An axis's rate is the Ixx15 of the motor assigned to it in this coordinate system,
  converted with that motor's scale factor (``#1->1000X``: counts per axis unit). With two or
  more motors on one axis the lowest rate is taken (the commanded axis stops last).
* An axis with no motor assigned decelerates at motor 1's Ixx15 with one count per axis unit
  (the simulator's axes need not have motors).
* Ixx15 <= 0 (the manual: "never 0") stops the axis at once.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class AbortStop:
    """Every axis decelerating from ``vel`` at ``pos`` (instant ``t0``) at its own rate; axis
    ``a`` comes to rest ``t_axis[a]`` seconds later."""

    t0: float
    pos: dict[str, float]
    vel: dict[str, float]
    t_axis: dict[str, float]

    @property
    def t_stop(self) -> float:
        """Seconds until the last axis is at rest."""
        return max(self.t_axis.values(), default=0.0)

    def positions(self, t: float) -> dict[str, float]:
        """Commanded positions at ``t`` (before ``t0``: where ``A`` found them): each axis on
        its own constant-deceleration ramp, then at rest."""
        out = {}
        tau_all = t - self.t0 if t > self.t0 else 0.0
        for a, p in self.pos.items():
            t_a = self.t_axis[a]
            if t_a <= 0.0:
                out[a] = p
                continue
            tau = tau_all if tau_all < t_a else t_a
            out[a] = p + self.vel[a] * (tau - tau * tau / (2.0 * t_a))
        return out

    def end(self) -> dict[str, float]:
        """Where every axis comes to rest."""
        return self.positions(self.t0 + self.t_stop)


def plan(
    t0: float, pos: Mapping[str, float], vel: Mapping[str, float],
    rate_of: Callable[[str], float],
) -> AbortStop:
    """The stop of every axis in ``pos`` from velocity ``vel`` (units/s; an axis missing from
    it stands still), ``rate_of(axis)`` giving its deceleration in units/s²."""
    v_axis = {a: vel.get(a, 0.0) for a in pos}
    t_axis = {}
    for a, v in v_axis.items():
        rate = rate_of(a)
        t_axis[a] = abs(v) / rate if v and rate > 0.0 else 0.0
    return AbortStop(t0, dict(pos), v_axis, t_axis)


__all__ = ["AbortStop", "plan"]
