"""Speed profiles along a move's path: trapezoids, triangles, endless ramps, cancellations.

A profile is piecewise constant acceleration: segments ``(tau0, s0, v0, acc)`` with ``tau``
the time since the move started and ``s`` the distance along the path. The controller's
profile generator works this way (spec §9.7, ``[INF]`` standard kinematics): accelerate at
ACCEL to SPEED, cruise, decelerate at DECEL to stop exactly at the end; a move too short to
reach SPEED is a triangle with peak speed sqrt(2·L·A·D/(A+D)). FORWARD / REVERSE ramp to SPEED
and run until cancelled; a CANCEL decelerates at DECEL from wherever the move is.

Positions are computed from the profile when asked (no event per servo period).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field


@dataclass(slots=True)
class Profile:
    """Distance along the path as a function of time since the move started.

    Attributes:
        segments: ``(tau0, s0, v0, acc)`` in time order.
        duration: total time in seconds (``math.inf`` for an endless move).
        length: total path distance (``math.inf`` for an endless move).
    """

    segments: list[tuple[float, float, float, float]] = field(default_factory=list)
    duration: float = 0.0
    length: float = 0.0

    def _segment(self, tau: float) -> tuple[float, float, float, float]:
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
        t0, s0, v0, a = self._segment(tau)
        dt = tau - t0
        return s0 + v0 * dt + 0.5 * a * dt * dt

    def v(self, tau: float) -> float:
        """Path speed ``tau`` seconds after the start."""
        if tau < 0.0 or tau >= self.duration or not self.segments:
            return 0.0
        t0, _s0, v0, a = self._segment(tau)
        return max(0.0, v0 + a * (tau - t0))

    def cancelled_at(self, tau: float, decel: float) -> Profile:
        """This profile until ``tau``, then a ramp down to rest at ``decel``."""
        tau = max(0.0, min(tau, self.duration))
        s0, v0 = self.s(tau), self.v(tau)
        keep = [seg for seg in self.segments if seg[0] < tau]
        t_stop = v0 / decel if v0 > 0.0 else 0.0
        keep.append((tau, s0, v0, -decel))
        length = s0 + v0 * t_stop - 0.5 * decel * t_stop * t_stop
        return Profile(keep, tau + t_stop, min(length, self.length))


def trapezoid(length: float, speed: float, accel: float, decel: float) -> Profile:
    """The move of ``length`` (>= 0) at ``speed`` with ``accel`` / ``decel`` ramps."""
    if length <= 0.0:
        return Profile([(0.0, 0.0, 0.0, 0.0)], 0.0, 0.0)
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
    segs = [(0.0, 0.0, 0.0, accel)]
    if t_cruise > 0.0:
        segs.append((t_acc, d_acc, v, 0.0))
    segs.append((t_acc + t_cruise, d_acc + v * t_cruise, v, -decel))
    return Profile(segs, t_acc + t_cruise + t_dec, length)


def endless(speed: float, accel: float) -> Profile:
    """FORWARD / REVERSE: ramp up to ``speed`` and keep going until cancelled."""
    t_acc = speed / accel
    segs = [(0.0, 0.0, 0.0, accel), (t_acc, speed * t_acc / 2.0, speed, 0.0)]
    return Profile(segs, math.inf, math.inf)


__all__ = ["Profile", "endless", "trapezoid"]
