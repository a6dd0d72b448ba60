"""Whole encoder edges, the repeat distance and the encoder / step ratios of an axis.

* Positions are counts of encoder edges (or stepper pulses): DPOS and MPOS are backed by
  integer counters and a fractional encoder-edge distance **above 0.9 is rounded up,
  otherwise down** (TJ1P-27, spec §9.2). :func:`whole_edges` applies that to the distance of
  every move when it starts (MOVE, MOVEABS, MOVECIRC, MHELICAL, MOVELINK, DATUM), so an axis
  at rest always sits on a whole edge: ``UNITS=1000`` then ``MOVE(0.00095)`` ends at
  ``DPOS 0.001`` (0.95 edge -> 1), ``MOVE(0.0005)`` does not move (0.5 edge -> 0). Between
  servo periods of a running move DPOS is read from the profile (``[INF]``: not rounded).
* ``REP_DIST`` / ``REP_OPTION`` bit 0 (TKB-REP, spec §11.5): REP_DIST is held as
  ``INT(REP_DIST x UNITS)`` counts; DPOS and MPOS read within -REP_DIST..+REP_DIST (bit 0 = 0)
  or 0..REP_DIST (bit 0 = 1) — :func:`wrap`. MOVEABS goes to its target inside that range,
  from the wrapped position ``[INF]``.
* ``ENCODER_RATIO(den, num)``: MPOS = num/den x encoder edges (TJCJ-159); the raw count the
  encoder reads, ``ENCODER``, is therefore MPOS x UNITS x den/num (:func:`encoder_count`).
"""

from __future__ import annotations

import math

#: TJ1P-27: a fraction of an edge above this is rounded up, otherwise down.
ROUND_UP_ABOVE = 0.9
_EPS = 1e-9


def whole_edges(distance: float, units: float) -> float:
    """``distance`` (user units) rounded to whole edges by the 0.9 rule, in user units."""
    if not math.isfinite(distance):
        return distance
    edges = abs(distance) * units
    n = math.floor(edges + _EPS)
    if edges - n > ROUND_UP_ABOVE + _EPS:
        n += 1
    return math.copysign(n / units, distance) if n else 0.0


def nearest_edge(position: float, units: float) -> float:
    """``position`` on the nearest whole edge (an axis coming to rest)."""
    if not math.isfinite(position):
        return position
    return math.floor(position * units + 0.5) / units


def wrap(position: float, units: float, rep_dist: float, rep_option: int) -> float:
    """DPOS / MPOS as read with REP_DIST and REP_OPTION bit 0 (the module docstring)."""
    r = int(rep_dist * units)
    if r <= 0:
        return position
    edges = position * units
    if rep_option & 1:
        if 0.0 <= edges < r:
            return position
        return (edges % r) / units
    if -r <= edges < r:
        return position
    return ((edges + r) % (2 * r) - r) / units


def encoder_count(mpos: float, units: float, ratio: tuple[float, float]) -> float:
    """ENCODER: the encoder edges that give ``mpos`` through ``ENCODER_RATIO(den, num)``."""
    den, num = ratio
    return mpos * units * den / num


__all__ = ["encoder_count", "nearest_edge", "whole_edges", "wrap"]
