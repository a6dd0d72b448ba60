"""Move timing and the commanded-position profile of a Turbo PMAC coordinate system.

Timing rules (spec §9.1; TSRM p188-189, p477; PUM p169, p175; Quick Ref p49):

* acceleration time ``Ta = max(TA, 2·TS)`` in whole ms (TA and TS rounded half up when
  executed);
* a LINEAR move's time is ``TM`` (move-by-time mode) or vector distance over the FRAX axes
  (X, Y, Z) ``/ F × Isx90`` ms (feedrate mode, the power-on mode with F = Isx89); a move with
  no FRAX distance uses the distance of all its axes ``[INF]``;
* a move never takes less than its ``Ta`` (``TM := max(TM, Ta)``); with TA = TS = 0 the minimum
  is 0.5 ms; at most 8 388 607 ms;
* moves are **blended**: ``TM`` runs between the centres of the acceleration ramps, each ramp
  ``Ta`` long and centred on the programmed point ``[INF, spec §9.1]``; the next move's ramp is
  clipped to ``Ta_next ≤ 2·(TM − Ta/2)``; a single move from rest therefore takes ``TM + Ta``
  (half a ramp up, TM, half a ramp down) and N blended moves ``N·TM + Ta``;
* ``DWELL t`` and ``DELAY t`` take t ms (DELAY is a zero-distance move, minimum Ta); RAPID
  moves each axis at Ixx22 counts/ms with Ixx21 ms of acceleration, the longest axis setting
  the time, never blended ``[INF]`` for the axis→motor mapping (motor 1's values are used);
* circles (CIRCLE1/2 with Isx13 > 0) take arc length / F and their commanded positions lie
  on the arc (:class:`Arc`; :mod:`motionsim.sim.pmac.modes.linear` adds the arc's offset
  from the chord to the blended chord profile of :func:`position_at`).

Positions are computed from the profile on demand: nothing runs per servo cycle. Ramps are
modelled with constant acceleration (the S-curve shape of TS is not modelled, only its time).
"""

from __future__ import annotations

import math
from collections.abc import Mapping

_floor = math.floor

#: Move kinds: what a calculated move is (index into :data:`motionsim.sim.pmac.modes.PROFILES`;
#: the ``#n?`` status reads DWELL, so the kinds sit here below the modes).
LINEAR, DWELL, DELAY, RAPID, PVT, SPLINE = 0, 1, 2, 3, 4, 5

MAX_MOVE_S = 8_388_607 / 1000.0
MIN_MOVE_S = 0.0005
FRAX = ("X", "Y", "Z")


def whole_ms(ms: float) -> int:
    """TA / TS as the controller uses them: whole milliseconds, halves rounded up
    (``TA0.5`` → 1 ms, ``TA2.5`` → 3 ms; not Python's round-half-to-even) ``[INF]``: the
    manual says only that they are used as integer ms (spec §9.1)."""
    return _floor(ms + 0.5)


def accel_time_s(ta_ms: float, ts_ms: float) -> float:
    """``Ta = max(TA, 2·TS)`` with TA and TS in whole ms (:func:`whole_ms`), in seconds."""
    return max(0, whole_ms(ta_ms), 2 * whole_ms(ts_ms)) / 1000.0


def clamp_move_time(t_s: float, ta_s: float) -> float:
    """A move takes at least its acceleration time (0.5 ms when that is 0), at most 8388.607 s."""
    return min(MAX_MOVE_S, max(t_s, ta_s, MIN_MOVE_S))


def vector_distance(delta: Mapping[str, float], frax: tuple[str, ...] = FRAX) -> float:
    """Vector distance over the feedrate axes, or over all axes when none of those move."""
    d = math.sqrt(sum(delta[a] ** 2 for a in frax if a in delta))
    if d == 0.0:
        d = math.sqrt(sum(v * v for v in delta.values()))
    return d


def feed_time_s(distance: float, feedrate: float, isx90_ms: float) -> float:
    """Time of a feedrate move: distance / F × Isx90 ms (F in units per Isx90 ms)."""
    if feedrate <= 0:
        return MAX_MOVE_S
    return distance / feedrate * isx90_ms / 1000.0


class Arc:
    """A CIRCLE move's arc in the XY plane: centre, radius, start angle and signed sweep
    (radians, negative clockwise: CIRCLE1). ``point(f)`` is the point a fraction ``f`` of the
    way along it."""

    __slots__ = ("cx", "cy", "r", "a0", "sweep")

    def __init__(self, cx: float, cy: float, r: float, a0: float, sweep: float) -> None:
        self.cx, self.cy, self.r, self.a0, self.sweep = cx, cy, r, a0, sweep

    @property
    def length(self) -> float:
        return self.r * abs(self.sweep)

    def point(self, f: float) -> tuple[float, float]:
        a = self.a0 + self.sweep * f
        return self.cx + self.r * math.cos(a), self.cy + self.r * math.sin(a)

    def tangent(self, f: float) -> tuple[float, float]:
        """d point / d f."""
        a = self.a0 + self.sweep * f
        k = self.r * self.sweep
        return -k * math.sin(a), k * math.cos(a)


def arc(
    start: Mapping[str, float],
    end: Mapping[str, float],
    centre: tuple[float, float] | None,
    radius: float | None,
    clockwise: bool,
    centre_absolute: bool = False,
) -> Arc | None:
    """The arc in the XY plane from ``start`` to ``end``, or None when there is none (a zero
    radius, or the R form with start = end: the chord is used ``[INF]``).

    ``centre`` is the I,J vector, from the start point (``INC(R)``, the default) or from the
    XYZ origin with ``centre_absolute`` (``ABS(R)``, TSRM p442: "radius vector"); ``radius``
    the R form (R > 0 the short arc, R < 0 the long one; the centre is to the right of the
    chord for a short clockwise arc). Same start and end with a centre vector is a full
    circle (seed 000: ``I100`` with no axis words).
    """
    x0, y0 = start.get("X", 0.0), start.get("Y", 0.0)
    x1, y1 = end.get("X", x0), end.get("Y", y0)
    if centre is not None:
        cx, cy = (centre if centre_absolute else (x0 + centre[0], y0 + centre[1]))
        r = math.hypot(x0 - cx, y0 - cy)
        if r == 0:
            return None
        a0 = math.atan2(y0 - cy, x0 - cx)
        a1 = math.atan2(y1 - cy, x1 - cx)
        sweep = ((a0 - a1) if clockwise else (a1 - a0)) % (2 * math.pi)
        if sweep < 1e-12:
            sweep = 2 * math.pi
        return Arc(cx, cy, r, a0, -sweep if clockwise else sweep)
    if not radius:
        return None
    dx, dy = x1 - x0, y1 - y0
    c = math.hypot(dx, dy)
    if c == 0:
        return None
    r = max(abs(radius), c / 2)  # an R shorter than half the chord: a half circle [INF]
    h = math.sqrt(max(0.0, r * r - c * c / 4)) / c
    # right of the chord: (dy, -dx); short CW arc and long CCW arc have their centre there
    side = 1.0 if (radius > 0) == clockwise else -1.0
    cx, cy = (x0 + x1) / 2 + side * h * dy, (y0 + y1) / 2 - side * h * dx
    ang = 2 * math.asin(min(1.0, c / (2 * r)))
    if radius < 0:
        ang = 2 * math.pi - ang
    return Arc(cx, cy, r, math.atan2(y0 - cy, x0 - cx), -ang if clockwise else ang)


def arc_length(
    start: Mapping[str, float],
    end: Mapping[str, float],
    centre: tuple[float, float] | None,
    radius: float | None,
    clockwise: bool,
    centre_absolute: bool = False,
) -> float:
    """Arc length in the XY plane from ``start`` to ``end`` (:func:`arc`); the chord when
    there is no arc."""
    a = arc(start, end, centre, radius, clockwise, centre_absolute)
    if a is not None:
        return a.length
    return math.hypot(end.get("X", start.get("X", 0.0)) - start.get("X", 0.0),
                      end.get("Y", start.get("Y", 0.0)) - start.get("Y", 0.0))


def ramp_position(x_s: float, v0: float, v1: float, tau: float, length: float) -> float:
    """Position ``tau`` into a constant-acceleration ramp from v0 to v1 lasting ``length``,
    starting at ``x_s``."""
    if length <= 0:
        return x_s + v1 * tau
    tau = min(max(tau, 0.0), length)
    return x_s + v0 * tau + (v1 - v0) * tau * tau / (2 * length)


def position_at(
    t: float,
    p_start: float,
    v: float,
    b_start: float,
    ta_in: float,
    v_prev: float,
    b_end: float | None = None,
    ta_out: float = 0.0,
    v_next: float = 0.0,
) -> float:
    """Commanded position of one axis at ``t`` within one move of the profile.

    The move passes its programmed start point ``p_start`` at ``b_start`` (the centre of the
    ramp from ``v_prev`` to ``v``, ``ta_in`` long) and runs at ``v``; if ``b_end`` is given the
    move ends there with a ramp to ``v_next`` (0 for a stop) of length ``ta_out``.
    """
    h_in = ta_in / 2
    if t < b_start + h_in:
        x_s = p_start - v_prev * h_in
        return ramp_position(x_s, v_prev, v, t - (b_start - h_in), ta_in)
    if b_end is not None and t > b_end - ta_out / 2:
        h = ta_out / 2
        x_s = p_start + v * (b_end - h - b_start)
        return ramp_position(x_s, v, v_next, t - (b_end - h), ta_out)
    return p_start + v * (t - b_start)


def velocity_at(
    t: float, v: float, b_start: float, ta_in: float, v_prev: float,
    b_end: float | None = None, ta_out: float = 0.0, v_next: float = 0.0,
) -> float:  # fmt: skip
    """Commanded velocity of one axis at ``t`` (same profile as :func:`position_at`)."""
    h_in = ta_in / 2
    if ta_in > 0 and t < b_start + h_in:
        f = min(max((t - (b_start - h_in)) / ta_in, 0.0), 1.0)
        return v_prev + (v - v_prev) * f
    if b_end is not None and t > b_end - ta_out / 2:
        if ta_out <= 0:
            return v_next
        f = min(max((t - (b_end - ta_out / 2)) / ta_out, 0.0), 1.0)
        return v + (v_next - v) * f
    return v


__all__ = [
    "DELAY", "DWELL", "LINEAR", "PVT", "RAPID", "SPLINE",
    "FRAX",
    "MAX_MOVE_S",
    "MIN_MOVE_S",
    "Arc",
    "accel_time_s",
    "arc",
    "arc_length",
    "clamp_move_time",
    "feed_time_s",
    "position_at",
    "ramp_position",
    "vector_distance",
    "velocity_at",
    "whole_ms",
]
