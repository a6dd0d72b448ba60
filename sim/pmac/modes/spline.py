"""SPLINE1 / SPLINE2 moves: the cubic B-spline through programmed points (TUM p290; PUM p183;
PUM-old p52; spec §11.2).

A move line in SPLINE mode gives each axis an ordinary position (ABS) or distance (INC); the
segment time is the move-time register, written by ``TM`` (I42 = 0; as for PVT, I42 = 1 and
``TA`` as the segment time are not modelled ``[INF]``). At every segment boundary ``i`` the
card computes a way-point and a velocity from the programmed point and its two neighbours —
uniform (SPLINE1): ``WP_i = (P_{i-1} + 4·P_i + P_{i+1}) / 6``, ``V_i = (P_{i+1} − P_{i-1}) /
2T`` — and each axis follows the one cubic that joins the boundaries' positions and
velocities (TUM p290). The path passes inside the programmed points; a move therefore needs
the *next* point before it can be calculated. At the start and the end of a series a
zero-distance segment of the same time is added (S-curve from and to rest, TUM p290), so N
points take (N + 2)·T: the added start segment is part of the first line's move, the added end
segment part of the last line's.

``[INF]`` decisions (no Turbo page gives them):

* SPLINE2 (non-uniform; TUM p290 says only "similar calculations"): with ``t1`` / ``t2`` the
  times of the segments into and out of point ``B`` (neighbours ``A``, ``C``), ``s1`` / ``s2``
  their mean velocities, ``V = (s1·t2 + s2·t1) / (t1 + t2)`` (the slope at ``B`` of the
  parabola through the three points) and ``WP = B + a·t1·t2 / 6`` with ``a = 2·(s2 − s1) /
  (t1 + t2)``; both reduce to the uniform formulas when ``t1 = t2``.
* SPLINE1 with a new segment time mid-series: the series so far is brought to a stop (its
  end segment added) and a new one starts from rest with the new time (PUM p183, PMAC(1)).
* The series ends at the next move of another mode, a DWELL / DELAY, or when the coordinate
  system runs out of points at a move's end (rotary run-out, end of program, ``Q``); with
  Isx92 = 1 every point is a series of its own.
* ``S`` (single step) runs one line's move and stops at its end boundary, a velocity step as
  with PVT (the manuals warn against stepping such sequences); the next ``S`` / ``R`` goes on
  from there.
* The segment time lies in the move-time register's range (0, 4095.9998] ms in steps of
  1/4096 ms (as PVT, TUM p292); outside it when a line is calculated is a run-time error.
* Ixx16 / Ixx17 do not limit a spline (PSRM p73-74 for PMAC(1); TSRM p98 names only LINEAR,
  segmented moves and RAPID).
"""

from __future__ import annotations

from . import pvt
from .hermite import rate_weights, weights
from .move import SPLINE, Move, PlanContext, Profile, RunTimeError

#: One piece of a spline move: its share ``(f0, f1)`` of the move's time, its start position
#: and tangent and its end position and tangent (tangents in units per piece, so the piece
#: keeps its shape when the time base stretches the move).
Piece = tuple[float, float, dict[str, float], dict[str, float], dict[str, float], dict[str, float]]
Pos = dict[str, float]
_SYNC = list[tuple[int, str, float]]


class SplineMove(Move):
    """A line's spline move: one cubic piece between two boundaries, plus the added start or
    end segment for the first / last line of a series."""

    __slots__ = ("pieces",)

    def __init__(self, n: int, tm: float, pieces: tuple[Piece, ...], sync: _SYNC | None) -> None:
        super().__init__(n, SPLINE, tm, 0.0, pieces[0][2], pieces[-1][4], sync)
        self.pieces = pieces


def segment_s(ms: float) -> float:
    """The segment time (program seconds) as the move-time register holds it; outside
    (0, 4095.9998] ms it is a run-time error."""
    if not 0 < ms <= pvt.MAX_SEGMENT_MS:
        raise RunTimeError(f"SPLINE segment time {ms:g} ms is outside (0, {pvt.MAX_SEGMENT_MS}]")
    return pvt.segment_ms(ms) / 1000.0


def boundary(a: Pos, b: Pos, c: Pos, t1: float, t2: float) -> tuple[Pos, Pos]:
    """Way-point and velocity (units/s) at point ``b`` between ``a`` and ``c``; ``t1`` / ``t2``
    are the times of the segments a→b and b→c (equal: the uniform spline)."""
    wp: Pos = {}
    v: Pos = {}
    k = t1 * t2 / 6.0
    for axis, pc in c.items():
        pa, pb = a.get(axis, 0.0), b.get(axis, 0.0)
        s1, s2 = (pb - pa) / t1, (pc - pb) / t2
        v[axis] = (s1 * t2 + s2 * t1) / (t1 + t2)
        wp[axis] = pb + 2.0 * (s2 - s1) / (t1 + t2) * k
    return wp, v


def _piece(wp0: Pos, v0: Pos, wp1: Pos, v1: Pos, t: float) -> tuple[Pos, Pos, Pos, Pos]:
    return wp0, {a: x * t for a, x in v0.items()}, wp1, {a: x * t for a, x in v1.items()}


class Series:
    """An open spline series of one coordinate system: the last point read (its move waits
    for the next point), the point before it, and the boundary its move starts from."""

    __slots__ = ("n", "point", "prev", "t", "wp0", "v0", "lead", "sync")

    def __init__(self, n: int, rest: Pos, point: Pos, t: float, sync: _SYNC) -> None:
        self.n, self.point, self.prev, self.t, self.sync = n, point, rest, t, sync
        # the added zero-distance segment: from rest at ``rest`` to the boundary at its end
        self.wp0, self.v0 = boundary(rest, rest, point, t, t)
        self.lead = True

    def _move(self, wp1: Pos, v1: Pos, tail: bool, scale: float) -> SplineMove:
        t = self.t
        if not (self.lead or tail):  # inside a series: one piece (the streamed case)
            one = (0.0, 1.0, *_piece(self.wp0, self.v0, wp1, v1, t))
            return SplineMove(self.n, t * scale, (one,), self.sync or None)
        parts = []
        if self.lead:
            parts.append(_piece(self.prev, {}, self.wp0, self.v0, t))  # from rest
        parts.append(_piece(self.wp0, self.v0, wp1, v1, t))
        if tail:
            end = self.point
            parts.append(_piece(wp1, v1, end, {}, t))
        k = len(parts)
        pieces = tuple((i / k, (i + 1) / k, *p) for i, p in enumerate(parts))
        return SplineMove(self.n, k * t * scale, pieces, self.sync or None)

    def add(self, n: int, point: Pos, t: float, sync: _SYNC, scale: float) -> SplineMove:
        """The next point arrives: the waiting point's move is calculated; ``point`` waits."""
        wp1, v1 = boundary(self.prev, self.point, point, self.t, t)
        move = self._move(wp1, v1, False, scale)
        self.prev, self.point, self.n, self.sync = self.point, point, n, sync
        self.t, self.wp0, self.v0, self.lead = t, wp1, v1, False
        return move

    def close(self, scale: float) -> SplineMove:
        """The series ends at the waiting point: its move, with the added end segment to rest."""
        p = self.point
        wp1, v1 = boundary(self.prev, p, p, self.t, self.t)
        return self._move(wp1, v1, True, scale)


def plan(
    ctx: PlanContext, series: Series | None, n: int, start: Pos, point: Pos, sync: _SYNC
) -> tuple[list[SplineMove], Series]:
    """Line ``n`` of a spline series reaches ``point`` (``start``: where the axes are before
    it). Returns the moves now calculated (the previous point's; or, in SPLINE1 after a new
    segment time, the stop of the old series) and the series, with ``point`` waiting."""
    t = segment_s(ctx.feedrate)
    uniform = ctx.mode == "SPLINE1"
    out: list[SplineMove] = []
    if series is not None and uniform and t != series.t:
        out.append(series.close(ctx.time_scale))  # PUM p183: stop, restart with the new time
        series = None
    if series is None:
        return out, Series(n, start, point, t, sync)
    out.append(series.add(n, point, t, sync, ctx.time_scale))
    return out, series


def _where(m: SplineMove, t: float) -> tuple[Piece, float, float]:
    """The piece executing at ``t``, the position in it (0..1) and its real duration."""
    span = m.b_end - m.b_start
    s = (t - m.b_start) / span if span > 0 else 1.0
    s = 0.0 if s < 0 else 1.0 if s > 1 else s
    for piece in m.pieces:
        if s <= piece[1]:
            break
    f0, f1 = piece[0], piece[1]
    return piece, (s - f0) / (f1 - f0), span * (f1 - f0)


class SplineProfile(Profile):
    """Each axis on the Hermite cubic of its piece; spline moves abut without a blend ramp,
    so the next one is needed only at this one's end (like PVT)."""

    kind = SPLINE
    blends = True
    family = "spline"
    decide_at_end = True
    stop_ramp = False

    def positions(self, m: Move, t: float) -> dict[str, float]:
        assert isinstance(m, SplineMove)
        (_, _, p0, m0, p1, m1), s, _ = _where(m, t)
        h00, h10, h01, h11 = weights(s)
        return {
            a: h00 * p0.get(a, 0.0) + h10 * m0.get(a, 0.0) + h01 * x + h11 * m1.get(a, 0.0)
            for a, x in p1.items()
        }

    def velocities(self, m: Move, t: float) -> dict[str, float]:
        assert isinstance(m, SplineMove)
        (_, _, p0, m0, p1, m1), s, dur = _where(m, t)
        if dur <= 0 or (m.stopping and t >= m.b_end):
            return dict.fromkeys(m.end, 0.0)
        g00, g10, g01, g11 = rate_weights(s)
        return {
            a: (g00 * p0.get(a, 0.0) + g10 * m0.get(a, 0.0) + g01 * x + g11 * m1.get(a, 0.0)) / dur
            for a, x in p1.items()
        }


PROFILE = SplineProfile()

__all__ = ["PROFILE", "Series", "SplineMove", "SplineProfile", "boundary", "plan", "segment_s"]
