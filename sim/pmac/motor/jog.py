"""One motor's jog / home trajectory: a piecewise constant-acceleration profile in counts.

What the Turbo PMAC does for jog and home moves (TSRM p100-101 Ixx19-Ixx22, p152 Ixx92;
PSRM p76; spec §11.3):

* the speed is Ixx22 (jog) or |Ixx23| (home, sign = direction), in counts/ms;
* the acceleration time is ``max(Ixx20, 2·Ixx21)`` ms (Ixx20 = 0: a pure S-curve of
  2·Ixx21); if that asks for more than Ixx19 counts/ms², the rate is clamped to Ixx19 and the
  time extended (the manual's example: Ixx20=100, Ixx21=0, Ixx22=50 asks 0.5 cts/ms²; with
  Ixx19=0.25 the ramp takes 200 ms);
* feedrate override does not apply.

Modelled here ``[INF]``: ramps are constant acceleration (the S-curve shape of Ixx21 is not
modelled, only its time, as for program moves in :mod:`motionsim.sim.pmac.buffers.motion`), and the
rate is fixed by the commanded speed — ``speed / accel time`` — so any change of velocity
(a ``J-`` while ``J+`` runs, a ``J/``) uses that same rate. A definite jog (``J=``, ``J^``,
``J:``) is a trapezoid (a triangle when too short to reach speed) that ends at rest on the
target; a motor moving away from the target first ramps to rest.

Nothing here knows about SimPy: a :class:`Profile` answers position and velocity at any
instant and the instant it comes to rest; :mod:`motionsim.sim.pmac.motor.motors` schedules it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

#: Rate used when Ixx19, Ixx20 and Ixx21 are all 0 (the manual forbids Ixx20 = Ixx21 = 0):
#: a velocity step, in counts/s².
_INSTANT = 1e12


@dataclass(frozen=True, slots=True)
class Segment:
    """From ``t0``: position ``p0`` (counts), velocity ``v0`` (counts/s), acceleration ``a``
    (counts/s²), until the next segment starts."""

    t0: float
    p0: float
    v0: float
    a: float

    def position(self, t: float) -> float:
        tau = t - self.t0
        return self.p0 + self.v0 * tau + 0.5 * self.a * tau * tau

    def velocity(self, t: float) -> float:
        return self.v0 + self.a * (t - self.t0)


@dataclass(frozen=True, slots=True)
class Profile:
    """A trajectory: ``segments`` in time order; ``t_end`` is when it comes to rest for good
    (None: it runs on at its last segment's constant velocity)."""

    segments: tuple[Segment, ...]
    t_end: float | None

    @staticmethod
    def rest(t: float, p: float) -> Profile:
        return Profile((Segment(t, p, 0.0, 0.0),), t)

    def _segment(self, t: float) -> Segment:
        segs = self.segments
        for s in reversed(segs):
            if s.t0 <= t:
                return s
        return segs[0]

    def position(self, t: float) -> float:
        if self.t_end is not None and t >= self.t_end:
            t = self.t_end
        return self._segment(t).position(t)

    def velocity(self, t: float) -> float:
        if self.t_end is not None and t >= self.t_end:
            return 0.0
        return self._segment(t).velocity(t)

    def crossing(self, t_from: float, level: float, rising: bool) -> float | None:
        """The first instant after ``t_from`` the position passes ``level`` going up
        (``rising``) or down, or None if it never does."""
        segs = self.segments
        for i, s in enumerate(segs):
            end = segs[i + 1].t0 if i + 1 < len(segs) else self.t_end
            if end is not None and end <= t_from:
                continue
            lo = max(t_from, s.t0)
            for tau in _roots(0.5 * s.a, s.v0, s.p0 - level):
                t = s.t0 + tau
                if t > lo and (end is None or t <= end):
                    v = s.velocity(t)
                    if (v > 0) if rising else (v < 0):
                        return t
        return None

    def shifted(self, dp: float) -> Profile:
        """The same motion with every position moved by ``dp`` (a new zero after homing)."""
        segs = tuple(Segment(s.t0, s.p0 + dp, s.v0, s.a) for s in self.segments)
        return Profile(segs, self.t_end)

    def then(self, new: Profile) -> Profile:
        """This profile until ``new`` starts, then ``new`` (a command acting later)."""
        t = new.segments[0].t0
        head = tuple(s for s in self.segments if s.t0 < t)
        return Profile(head + new.segments, new.t_end)


def _roots(a: float, b: float, c: float) -> list[float]:
    """Real roots of ``a·x² + b·x + c``, ascending."""
    if a == 0:
        return [] if b == 0 else [-c / b]
    d = b * b - 4 * a * c
    if d < 0:
        return []
    r = math.sqrt(d)
    return sorted(((-b - r) / (2 * a), (-b + r) / (2 * a)))


def ramp_rate(speed: float, i19: float, i20: float, i21: float) -> float:
    """Acceleration in counts/ms² for a jog / home at ``speed`` counts/ms (TSRM p100-101)."""
    ta_ms = max(i20, 2.0 * i21, 0.0)
    speed = abs(speed)
    rate = speed / ta_ms if ta_ms > 0 else math.inf
    if i19 > 0 and rate > i19:
        rate = i19
    return rate


def _rate_s(rate_ms2: float) -> float:
    """counts/ms² -> counts/s² (a velocity step when the rate is unbounded)."""
    return rate_ms2 * 1e6 if math.isfinite(rate_ms2) and rate_ms2 > 0 else _INSTANT


def to_velocity(t0: float, p0: float, v0: float, v1: float, rate_ms2: float) -> Profile:
    """From (p0, v0) at ``t0``, ramp to ``v1`` counts/s and hold it (``v1 = 0``: stop)."""
    a = _rate_s(rate_ms2)
    dv = v1 - v0
    if dv == 0:
        return Profile((Segment(t0, p0, v0, 0.0),), t0 if v1 == 0 else None)
    acc = math.copysign(a, dv)
    t1 = t0 + abs(dv) / a
    s = Segment(t0, p0, v0, acc)
    tail = Segment(t1, s.position(t1), v1, 0.0)
    return Profile((s, tail), t1 if v1 == 0 else None)


def to_position(
    t0: float, p0: float, v0: float, target: float, speed: float, rate_ms2: float
) -> Profile:
    """From (p0, v0) at ``t0`` to rest at ``target`` (counts), at most ``speed`` counts/s."""
    a = _rate_s(rate_ms2)
    vmax = abs(speed)
    d = target - p0
    stop_d = v0 * v0 / (2 * a)
    if v0 != 0 and (d * v0 < 0 or stop_d > abs(d) + 1e-9):
        # moving away, or too fast to stop in time: come to rest first
        first = to_velocity(t0, p0, v0, 0.0, rate_ms2)
        t1 = first.t_end
        assert t1 is not None
        rest = to_position(t1, first.position(t1), 0.0, target, speed, rate_ms2)
        return Profile(first.segments[:-1] + rest.segments, rest.t_end)
    if d == 0:
        return Profile.rest(t0, p0)
    sign = 1.0 if d > 0 else -1.0
    dist, u = abs(d), abs(v0)
    vp = math.sqrt((2 * a * dist + u * u) / 2)  # peak of a triangle from u
    segs: list[Segment] = []
    t, p = t0, p0
    if vp <= vmax or vmax <= 0:
        t_up = (vp - u) / a
        segs.append(Segment(t, p, sign * u, sign * a))
        t += t_up
        p = segs[-1].position(t)
        v = vp
    else:
        # ramp u -> vmax (up or down), cruise, ramp down
        acc = a if vmax >= u else -a
        d_ramp = abs(vmax * vmax - u * u) / (2 * a)
        d_down = vmax * vmax / (2 * a)
        cruise = dist - d_ramp - d_down
        if u != vmax:
            segs.append(Segment(t, p, sign * u, sign * acc))
            t += abs(vmax - u) / a
            p = segs[-1].position(t)
        segs.append(Segment(t, p, sign * vmax, 0.0))
        t += max(0.0, cruise) / vmax
        p = segs[-1].position(t)
        v = vmax
    segs.append(Segment(t, p, sign * v, -sign * a))
    t_end = t + v / a
    segs.append(Segment(t_end, target, 0.0, 0.0))
    return Profile(tuple(segs), t_end)


__all__ = ["Profile", "Segment", "ramp_rate", "to_position", "to_velocity"]
