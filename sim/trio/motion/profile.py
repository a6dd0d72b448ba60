"""Speed profiles along a move's path: trapezoids, triangles, S-ramps, merges, cancellations.

A profile is piecewise constant jerk: segments ``(tau0, s0, v0, a0, jerk)`` with ``tau`` the
time since the move started and ``s`` the distance along the path. The controller's profile
generator (spec §9.7, ``[INF]`` standard kinematics): accelerate at ACCEL to SPEED, cruise,
decelerate at DECEL to stop exactly at the end; a move too short to reach SPEED is a triangle
with peak speed sqrt(2·L·A·D/(A+D)). FORWARD / REVERSE ramp to SPEED and run until cancelled;
a CANCEL decelerates at DECEL from wherever the move is.

SRAMP (MC2xx axis parameter) — not found in any corpus reachable here (searched docs, pages,
issues, code and find_string for "SRAMP", "Trio SRAMP S ramp", "Trio Motion Coordinator SRAMP axis
parameter S-curve"; spec §9.7 and §9.11 list it as ``[BK]``). Modelled from the MC2xx TRM as
the engineer remembers it, ``[BK]``: SRAMP is the time in **milliseconds** (0..250) over which
the acceleration itself ramps from 0 to ACCEL (or DECEL) and back, giving S-shaped speed
ramps; ACCEL / DECEL stay the peak rates, so each speed change of ``dv`` takes ``dv/A + Ts``
(``Ts`` = SRAMP in s) when ``dv >= A·Ts``, else ``2·sqrt(dv·Ts/A)`` with a peak acceleration
below A. A trapezoid move that reaches SPEED therefore lasts exactly SRAMP longer than with
SRAMP = 0 (the same figure a moving-average filter of SRAMP on the speed gives). SRAMP = 0 is
today's trapezoid. A CANCEL ramps down at DECEL with the same S (starting from zero
acceleration, ``[INF]``), so a cancelled S-ramped move does not jerk to a stop.

Merged moves (see :mod:`motionsim.sim.trio.motion.buffers`) start at the speed the previous move
ended with
(``v0``) and, when the next move is merged onto them, end at speed (``stop=False``): no
deceleration at their end. If a move cannot stop within its length from ``v0`` at DECEL, it
decelerates over its whole length at the rate that stops it exactly at the end (``[INF]``:
the TRM warns that short merged moves need a high DECEL).

Positions are computed from the profile when asked (no event per servo period).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field

Segment = tuple[float, float, float, float, float]  # tau0, s0, v0, a0, jerk


@dataclass(slots=True)
class Profile:
    """Distance along the path as a function of time since the move started.

    Nothing changes a profile's segments once made (a re-plan, a merge or a CANCEL makes a new
    profile), so profiles may share one list (:func:`trapezoid` does). A profile's identity
    tells a re-planned move from the plan it had (``guards.py``): every move gets its own.

    Attributes:
        segments: ``(tau0, s0, v0, a0, jerk)`` in time order.
        duration: total time in seconds (``math.inf`` for an endless move).
        length: total path distance (``math.inf`` for an endless move).
        v_end: path speed at the end (0 unless the move ends merged into the next one).
    """

    segments: list[Segment] = field(default_factory=list)
    duration: float = 0.0
    length: float = 0.0
    v_end: float = 0.0

    def _segment(self, tau: float) -> Segment:
        seg = self.segments[0]
        for cand in self.segments:
            if cand[0] <= tau:
                seg = cand
            else:
                break
        return seg

    def s(self, tau: float) -> float:
        """Distance travelled ``tau`` seconds after the start (clamped to the move)."""
        if tau <= 0.0 or not self.segments:
            return 0.0
        if tau >= self.duration:
            return self.length
        t0, s0, v0, a, j = self._segment(tau)
        dt = tau - t0
        return s0 + dt * (v0 + dt * (0.5 * a + dt * j / 6.0))

    def v(self, tau: float) -> float:
        """Path speed ``tau`` seconds after the start."""
        if tau < 0.0 or not self.segments:
            return 0.0
        if tau >= self.duration:
            return self.v_end if self.duration != math.inf else 0.0
        t0, _s0, v0, a, j = self._segment(tau)
        dt = tau - t0
        return max(0.0, v0 + dt * (a + 0.5 * j * dt))

    def accel(self, tau: float) -> float:
        """Path acceleration ``tau`` seconds after the start (0 outside the move)."""
        if tau < 0.0 or tau >= self.duration or not self.segments:
            return 0.0
        t0, _s0, _v0, a, j = self._segment(tau)
        return a + j * (tau - t0)

    def time_at(self, s: float) -> float:
        """The first ``tau`` at which the distance travelled reaches ``s`` (``math.inf`` when
        it never does); ``s`` runs on monotonically, so each segment is bisected."""
        if s <= 0.0:
            return 0.0
        if s > self.length:
            return math.inf
        segs = self.segments
        for i, (t0, s0, v0, a, j) in enumerate(segs):
            t1 = segs[i + 1][0] if i + 1 < len(segs) else self.duration
            s1 = segs[i + 1][1] if i + 1 < len(segs) else self.length
            if s > s1:
                continue
            if t1 == math.inf:  # an endless cruise
                if a == 0.0 and j == 0.0:
                    return t0 + (s - s0) / v0 if v0 > 0.0 else math.inf
                t1 = t0 + 1.0
                while self.s(t1) < s:
                    t1 = t0 + 2.0 * (t1 - t0)
            return _solve(lambda tau: self.s(tau) - s, t0, t1)
        return self.duration

    def cancelled_at(self, tau: float, decel: float, sramp_s: float = 0.0) -> Profile:
        """This profile until ``tau``, then a ramp down to rest at ``decel`` — S-shaped over
        ``sramp_s`` (SRAMP) when it is not 0, from zero acceleration ``[INF]``."""
        tau = max(0.0, min(tau, self.duration))
        s0, v0 = self.s(tau), self.v(tau)
        keep = [seg for seg in self.segments if seg[0] < tau]
        if sramp_s > 0.0 and v0 > 0.0:
            t_end, length = _ramp(keep, tau, s0, v0, 0.0, decel, sramp_s)
            keep.append((t_end, length, 0.0, 0.0, 0.0))
            return Profile(keep, t_end, min(length, self.length))
        t_stop = v0 / decel if v0 > 0.0 else 0.0
        keep.append((tau, s0, v0, -decel, 0.0))
        length = s0 + v0 * t_stop - 0.5 * decel * t_stop * t_stop
        return Profile(keep, tau + t_stop, min(length, self.length))


# -- speed ramps ---------------------------------------------------------------------------


def ramp_time(dv: float, rate: float, ts: float) -> float:
    """Time to change speed by ``dv`` (>= 0) at peak ``rate`` with an S-ramp of ``ts`` s."""
    if dv <= 0.0:
        return 0.0
    if ts <= 0.0:
        return dv / rate
    if dv >= rate * ts:
        return dv / rate + ts
    return 2.0 * math.sqrt(dv * ts / rate)


def ramp_distance(v_from: float, v_to: float, rate: float, ts: float) -> float:
    """Distance covered while ramping from ``v_from`` to ``v_to`` (symmetric ramp)."""
    return 0.5 * (v_from + v_to) * ramp_time(abs(v_to - v_from), rate, ts)


def _ramp(segs: list[Segment], tau: float, s: float, v0: float, v1: float,
          rate: float, ts: float) -> tuple[float, float]:
    """Append the segments of a ramp ``v0`` -> ``v1``; returns ``(tau, s)`` at its end."""
    dv = v1 - v0
    if dv == 0.0:
        return tau, s
    sign = 1.0 if dv > 0.0 else -1.0
    dv = abs(dv)
    if ts <= 0.0:
        segs.append((tau, s, v0, sign * rate, 0.0))
        t = dv / rate
        return tau + t, s + 0.5 * (v0 + v1) * t
    if dv >= rate * ts:
        jerk, a_peak, t_j, t_c = rate / ts, rate, ts, dv / rate - ts
    else:
        t_j = math.sqrt(dv * ts / rate)
        jerk, t_c = rate / ts, 0.0
        a_peak = jerk * t_j
    jerk, a_peak = sign * jerk, sign * a_peak
    t_total = 2.0 * t_j + t_c
    phases = ((t_j, 0.0, jerk), (t_c, a_peak, 0.0), (t_j, a_peak, -jerk))
    v, tt, ss = v0, tau, s
    for dt, a, j in phases:
        if dt <= 0.0:
            continue
        segs.append((tt, ss, v, a, j))
        ss += dt * (v + dt * (0.5 * a + dt * j / 6.0))
        v += dt * (a + 0.5 * j * dt)
        tt += dt
    return tau + t_total, s + 0.5 * (v0 + v1) * t_total


def _solve(f, lo: float, hi: float) -> float:
    """The root of increasing ``f`` on ``[lo, hi]`` (``f(lo) <= 0 <= f(hi)``), by bisection."""
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        if f(mid) > 0.0:
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


def trapezoid(length: float, speed: float, accel: float, decel: float) -> Profile:
    """The move of ``length`` (>= 0) at ``speed`` with ``accel`` / ``decel`` ramps: a new
    :class:`Profile` of :func:`_trapezoid`'s segments, planned once for each set of
    arguments (the last 4 096: a program repeating a move plans it once)."""
    return Profile(*_trapezoid(length, speed, accel, decel))


@functools.lru_cache(maxsize=4096, typed=True)
def _trapezoid(length: float, speed: float, accel: float,
               decel: float) -> tuple[list[Segment], float, float]:
    """The segments, duration and length of :func:`trapezoid` (the segments shared by the
    profiles made of them, never changed)."""
    if length <= 0.0:
        return [(0.0, 0.0, 0.0, 0.0, 0.0)], 0.0, 0.0
    d_acc = speed * speed / (2.0 * accel)
    d_dec = speed * speed / (2.0 * decel)
    if d_acc + d_dec <= length:
        v = speed
        t_acc, t_dec = v / accel, v / decel
        t_cruise = (length - d_acc - d_dec) / v
    else:
        v = math.sqrt(2.0 * length * accel * decel / (accel + decel))
        t_acc, t_dec = v / accel, v / decel
        t_cruise = 0.0
        d_acc = v * v / (2.0 * accel)
    segs: list[Segment] = [(0.0, 0.0, 0.0, accel, 0.0)]
    if t_cruise > 0.0:
        segs.append((t_acc, d_acc, v, 0.0, 0.0))
    segs.append((t_acc + t_cruise, d_acc + v * t_cruise, v, -decel, 0.0))
    return segs, t_acc + t_cruise + t_dec, length


def plan(length: float, speed: float, accel: float, decel: float, *, sramp_s: float = 0.0,
         v0: float = 0.0, stop: bool = True) -> Profile:
    """The profile of a move of ``length`` starting at path speed ``v0``.

    ``stop`` False: the move ends at speed (the next move is merged onto it), so it only
    ramps towards SPEED and cruises. Speeding up uses ACCEL, slowing down DECEL; both ramps
    are S-shaped over ``sramp_s`` seconds.
    """
    if v0 == 0.0 and sramp_s <= 0.0 and stop:
        return trapezoid(length, speed, accel, decel)
    if length <= 0.0:
        return Profile([(0.0, 0.0, v0, 0.0, 0.0)], 0.0, 0.0, v0 if not stop else 0.0)

    def rate(a: float, b: float) -> float:
        return accel if b > a else decel

    def up(v: float) -> float:
        return ramp_distance(v0, v, rate(v0, v), sramp_s)

    segs: list[Segment] = []
    if not stop:
        if up(speed) <= length:
            v1 = speed
        elif speed > v0:  # the move ends before SPEED is reached
            v1 = _solve(lambda v: up(v) - length, v0, speed)
        else:  # slowing down to SPEED takes longer than the move
            v1 = _solve(lambda v: length - up(v), speed, v0)
        tau, s = _ramp(segs, 0.0, 0.0, v0, v1, rate(v0, v1), sramp_s)
        if s < length and v1 > 0.0:
            segs.append((tau, s, v1, 0.0, 0.0))
            tau += (length - s) / v1
        if not segs:
            segs.append((0.0, 0.0, v0, 0.0, 0.0))
        return Profile(segs, tau, length, v1)

    def total(v: float) -> float:
        return up(v) + ramp_distance(v, 0.0, decel, sramp_s)

    stopping = ramp_distance(v0, 0.0, decel, sramp_s)
    if stopping > length:  # cannot stop in time at DECEL: stop over the whole length
        r = v0 * v0 / (2.0 * length)
        segs.append((0.0, 0.0, v0, -r, 0.0))
        return Profile(segs, v0 / r, length)
    if total(speed) <= length:
        vp = speed
    elif v0 <= speed:
        vp = _solve(lambda v: total(v) - length, v0, speed)
    else:
        vp = v0  # faster than SPEED and no room to slow to it first: hold v0, then stop
    tau, s = _ramp(segs, 0.0, 0.0, v0, vp, rate(v0, vp), sramp_s)
    d_stop = ramp_distance(vp, 0.0, decel, sramp_s)
    cruise = length - s - d_stop
    if cruise > 0.0 and vp > 0.0:
        segs.append((tau, s, vp, 0.0, 0.0))
        tau += cruise / vp
        s = length - d_stop
    tau, _s = _ramp(segs, tau, s, vp, 0.0, decel, sramp_s)
    return Profile(segs, tau, length)


def endless(speed: float, accel: float, sramp_s: float = 0.0, v0: float = 0.0) -> Profile:
    """FORWARD / REVERSE: ramp from ``v0`` to ``speed`` at ``accel`` (the rate of the change,
    up or down) and keep going until cancelled."""
    segs: list[Segment] = []
    tau, s = _ramp(segs, 0.0, 0.0, v0, speed, accel, sramp_s)
    segs.append((tau, s, speed, 0.0, 0.0))
    return Profile(segs, math.inf, math.inf)


def hold(v0: float, decel: float, length: float) -> Profile:
    """SPEED = 0: ramp down from ``v0`` at ``decel`` and stay there (the move is not over;
    ``length`` is what it still has to go). A ramp longer than ``length`` is shortened to stop
    at the end (``[INF]``)."""
    segs: list[Segment] = []
    if v0 > 0.0:
        rate = decel
        if v0 * v0 / (2.0 * rate) > length:
            rate = v0 * v0 / (2.0 * length)
        t_stop = v0 / rate
        segs.append((0.0, 0.0, v0, -rate, 0.0))
        segs.append((t_stop, 0.5 * v0 * t_stop, 0.0, 0.0, 0.0))
    else:
        segs.append((0.0, 0.0, 0.0, 0.0, 0.0))
    return Profile(segs, math.inf, length)


def diverges_at(a: Profile, b: Profile) -> float:
    """The first instant from which profiles ``a`` and ``b`` differ (``inf`` if never)."""
    for sa, sb in zip(a.segments, b.segments, strict=False):
        if any(abs(x - y) > 1e-9 * max(1.0, abs(x)) for x, y in zip(sa, sb, strict=True)):
            return min(sa[0], sb[0])
    n = min(len(a.segments), len(b.segments))
    rest = a.segments[n:] or b.segments[n:]
    return rest[0][0] if rest else min(a.duration, b.duration)


__all__ = ["Profile", "diverges_at", "endless", "hold", "plan", "ramp_distance", "ramp_time",
           "trapezoid"]
