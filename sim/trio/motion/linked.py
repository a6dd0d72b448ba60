"""Moves linked to another axis or to the TABLE: CONNECT, CAM, CAMBOX, MOVELINK.

They go through the process buffer, NTYPE and MTYPE like every move (TN20, M206-320) and
report their MTYPE code there: CAM 13, CAMBOX 20, CONNECT 21, MOVELINK 22 (spec §10.1). While
in MTYPE the base axis' demand position is computed, when read, from the link axis' position
at the same servo period (the master's *measured* position; MPOS = DPOS in this simulator), or
from time for CAM. Sources (spec §10.3):

* ``CONNECT(ratio, driving_axis)`` — electronic gearbox: the base axis follows the driving
  axis' movement times ``ratio``, in encoder edges out per edge in (UNITS of neither axis
  applied), from where both were when it started; it never ends by itself, only by CANCEL or
  RAPIDSTOP (TJ2P-71, Trio KB "CONNECT command"). A new CONNECT on an axis connected to the
  same driving axis changes the ratio, without a step, at the servo period it is transferred
  (TJ2P-71); one naming another driving axis waits until the first is CANCELled. CLUTCH_RATE
  (ramped ratio changes) is not modelled.
* ``CAM(start, end, multiplier, distance)`` — the base axis follows the TABLE points
  ``start..end`` (linearly interpolated); the table values are absolute positions from the
  start of the motion in encoder edges, scaled by ``multiplier`` (TRM p. 8-17, MC206 listing
  p. 207). The progress through the table runs over ``distance`` user units at the base axis'
  SPEED, ramped at ACCEL / DECEL like a move (same page: "the SPEED is ramped up to using the
  current ACCEL value"; 100 mm at 10 mm/s take 10 s), so SPEED changed while it runs changes
  its rate. ENDMOVE keeps the end of the previous move (TJ1P-54).
* ``CAMBOX(start, end, multiplier, link_dist, link_axis[, link_options[, link_pos]])`` — the
  same TABLE profile (absolute positions from the start, encoder edges, times the multiplier),
  driven by ``link_dist`` user units of the link axis' measured movement instead of time
  (TRM p. 8-19, MC206 listing p. 209; TJ2P-56). The cam runs backwards when the link axis does
  (TJ2P-56) and ends when the link axis has moved ``link_dist`` from the start; REMAIN is the
  link distance still to go.
* ``MOVELINK(distance, link_dist, link_acc, link_dec, link_axis[, link_options[, link_pos]])``
  — the base axis moves ``distance`` while the link axis moves ``link_dist``, ramping its ratio
  up over the first ``link_acc`` and down over the last ``link_dec`` of the link distance; when
  ``link_acc + link_dec > link_dist`` both are scaled down in proportion (MOVELINK help text,
  spec §10.3). The link axis may move either way ``[INF]``: the progress is the distance it
  has moved, in either direction.

``link_options`` other than 0 (start on MARK, at ``link_pos``, repeat, direction only, ...)
are refused as not simulated when the statement runs.

A linked move that ends by link distance (CAMBOX, MOVELINK) is checked once per servo period
while it runs — the only per-period work of the Trio model; CANCEL stops a linked move at once
where it is (``[BK]``: only speed-profiled moves ramp down at DECEL).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING

from ..card.basic_errors import BasicError
from ..card.scaling import whole_edges
from ..language.move_words import LINKED
from .link_options import PATTERN, check_options, ramp_of
from .link_run import LinkRun, check_pattern
from .moves import Move
from .profile import Profile

if TYPE_CHECKING:
    from .axis import Axis

_HOLD = Profile([(0.0, 0.0, 0.0, 0.0, 0.0)], math.inf, math.inf)


def movelink_shape(dist: float, link_dist: float, link_acc: float, link_dec: float,
                   base_dist: float, ramp: Callable[[float], float]) -> Callable[[float], float]:
    """MOVELINK's displacement after ``x`` of the link distance (MOVELINK-MD).

    ``base_dist`` of ``dist`` is run at the constant base ratio base_dist / link_dist over the
    whole link distance; the rest rides on it as the usual profile: the ratio ramps up over
    ``link_acc`` and down over ``link_dec`` (both scaled down in proportion when they add up
    to more than ``link_dist``), so the move starts and ends at the base ratio (MOVELINK-MD
    example 5: a decel from ratio 1 to 1:3 with base distance 30 of 60 over 90). ``ramp``
    is the ramp shape's integral (:mod:`motionsim.sim.trio.motion.link_options`)."""
    la, ld = link_acc, link_dec
    if la + ld > link_dist:
        k = link_dist / (la + ld)
        la, ld = la * k, ld * k
    r_base = base_dist / link_dist
    rest = dist - base_dist
    r = rest / (link_dist - 0.5 * (la + ld))

    def shape(x: float) -> float:
        if x <= 0.0:
            return 0.0
        if x >= link_dist:
            return dist
        if x < la:
            d = r * la * ramp(x / la)
        elif x <= link_dist - ld:
            d = r * (0.5 * la + (x - la))
        else:
            d = rest - r * ld * ramp((link_dist - x) / ld)
        return r_base * x + d

    return shape


def link_axis_of(kind: str, args: tuple[float, ...]) -> int | None:
    """The axis a linked command follows (None for CAM)."""
    i = LINKED[kind][2]
    return None if i is None else int(args[i])


def check_linked(kind: str, args: tuple[float, ...], base: int, table_size: int) -> None:
    """Run-time checks of a linked command's arguments (a BasicError stops the process)."""
    link = link_axis_of(kind, args)
    if link is not None and link == base:
        raise BasicError(f"{kind}: the link axis must not be the base axis ({base})")
    options = check_options(kind, args[5]) if len(args) > 5 else 0
    if kind == "CAMBOX" and len(args) > 7:
        raise BasicError("CAMBOX offset_start (link_options bit 7) not simulated")
    if kind == "CAMBOX" and options & PATTERN:
        check_pattern({}, args[2], table_size)
    if kind in ("CAM", "CAMBOX"):
        start, end = int(args[0]), int(args[1])
        if not (0 <= start < table_size and 0 <= end < table_size) or start == end:
            raise BasicError(f"{kind}: TABLE points {start}..{end} out of range")
    if kind in ("CAMBOX", "MOVELINK") and not args[1 if kind == "MOVELINK" else 3] > 0:
        raise BasicError(f"{kind}: the link distance must be positive")
    if kind == "CAM" and args[3] == 0:
        raise BasicError("CAM: the distance must not be 0")


class LinkedMove(Move):
    """CONNECT, CAM, CAMBOX or MOVELINK on one base axis."""

    __slots__ = ("link", "m0", "table_pts", "scale", "done_pos", "ratio_now", "clutch",
                 "base_units", "t_last", "run", "table")

    def bind(self, link: Axis | None, table: list[float],
             table_store: dict[int, float] | None = None, offset_first: bool = False) -> None:
        """Give the move its link axis and (CAM/CAMBOX) its TABLE points, as they are when the
        command is issued (``[INF]``: TABLE writes during the cam do not reach it), and the
        TABLE itself (a pattern-mode control block is read and written while it runs).

        ``offset_first`` (MC4xx): CAMBOX's TABLE values are offset by the first one before the
        multiplier, so a profile not starting at 0 does not jump (CAMBOX-MD); on the MC2xx
        generation they are positions from the start as they stand (M206-209)."""
        self.link = link
        if offset_first and self.kind == "CAMBOX" and table:
            table = [v - table[0] for v in table]
        self.table_pts = table
        self.table = table_store if table_store is not None else {}
        self.run: LinkRun | None = None
        self.m0 = 0.0
        self.scale = 1.0
        self.done_pos: float | None = None
        self.geom = self.kind
        self.ratio_now = 0.0  # CONNECT: the ratio in use (ramping at CLUTCH_RATE)
        self.clutch = 0.0  # CLUTCH_RATE when the ratio last changed (0: at once)

    # -- shape -----------------------------------------------------------------------------

    def begin(self, tick: int, t_start: float, axes: list[Axis], v0: float = 0.0) -> None:
        base = axes[0]
        self.p0 = (base.own_position(),)
        self.start_tick, self.t_start = tick, t_start
        kind, a = self.kind, self.args
        if self.link is not None:
            self.m0 = self.link.position(t_start)
        self.unit = (1.0,)
        if kind == "CAM":
            self.scale = a[2] / base.units
            self._plan(abs(a[3]), base.speed, base.accel, base.decel, base.sramp / 1000.0)
            self.end_pos = (self._cam(1.0),)
        elif kind == "CAMBOX" or kind == "MOVELINK":
            options = int(a[5]) if len(a) > 5 else 0
            self.profile = _HOLD
            assert self.link is not None
            if kind == "CAMBOX":
                self.length = a[3]
                units = base.units
                run = LinkRun(kind, options, a[3], self.link, a[6] if len(a) > 6 else 0.0,
                              base, self.table,
                              lambda x, mult: self._table_at(x / a[3]) * mult / units, a[2])
                self.scale = a[2] / base.units
                self.end_pos = (self._cam(1.0),)
            else:
                self.length = a[1]
                dist = whole_edges(a[0], base.units)
                shape = movelink_shape(dist, a[1], a[2], a[3], a[7] if len(a) > 7 else 0.0,
                                       ramp_of(options))
                run = LinkRun(kind, options, a[1], self.link, a[6] if len(a) > 6 else 0.0,
                              base, self.table, lambda x, _mult: shape(x), 1.0)
                self.end_pos = (self.p0[0] + dist,)
            run.start(t_start, self.p0[0])
            self.run = run
        else:  # CONNECT
            assert self.link is not None
            self.length = math.inf
            self.profile = _HOLD
            self.end_pos = self.p0
            self.clutch = base.stored.values["CLUTCH_RATE"]
            self.base_units, self.t_last = base.units, t_start
            self.ratio_now = 0.0 if self.clutch > 0.0 else a[0]
            self.scale = self.ratio_now * self.link.units / base.units

    def _table_at(self, f: float) -> float:
        """The TABLE profile a fraction ``f`` (0..1) along, linearly interpolated."""
        pts = self.table_pts
        x = min(max(f, 0.0), 1.0) * (len(pts) - 1)
        i = min(int(x), len(pts) - 2)
        return pts[i] + (pts[i + 1] - pts[i]) * (x - i)

    def _cam(self, f: float) -> float:
        return self.p0[0] + self._table_at(f) * self.scale

    def _at(self, s: float) -> tuple[float, ...]:
        """CAM: the table position a distance ``s`` into the cam."""
        return (self._cam(s / self.length if self.length > 0.0 else 1.0),)

    def progress(self, t: float) -> float:
        """Link-axis distance moved since the start, at servo instant ``t``."""
        assert self.link is not None
        return self.link.position(t) - self.m0

    def positions(self, tau: float) -> tuple[float, ...]:
        kind = self.kind
        if kind == "CAM":
            return super().positions(tau)
        if self.done_pos is not None:
            return (self.done_pos,)
        t = self.t_start + tau
        if kind == "CONNECT":
            return (self.p0[0] + self.scale * self.progress(t),)
        assert self.run is not None
        return (self.run.position(),)

    def rebase_ratio(self, t: float, ratio: float, base: Axis) -> None:
        """CONNECT's ratio changed at servo instant ``t``: follow on from where both axes are
        — at once, or ramping at the base axis' CLUTCH_RATE (:meth:`tick`)."""
        assert self.link is not None
        here = self.positions(t - self.t_start)[0]
        self.p0 = (here,)
        self.m0 = self.link.position(t)
        self.args = (ratio, *self.args[1:])
        self.clutch = base.stored.values["CLUTCH_RATE"]
        self.base_units, self.t_last = base.units, t
        if self.clutch <= 0.0:
            self.ratio_now = ratio
        self.scale = self.ratio_now * self.link.units / base.units

    def needs_tick(self) -> bool:
        """CAMBOX / MOVELINK end by link distance; a CONNECT ramps its ratio per period."""
        if self.kind == "CONNECT":
            return self.ratio_now != self.args[0]
        return self.kind != "CAM"

    def tick(self, t: float) -> str | None:
        if self.kind == "CONNECT":
            return None if self._clutch_step(t) else "idle"
        return "end" if self.link_done(t) else None

    def _clutch_step(self, t: float) -> bool:
        """CLUTCH_RATE (TJ2P-71: it ramps CONNECT's ratio changes; ratio per second
        ``[BK]``): each servo period the ratio moves towards the target by CLUTCH_RATE x the
        period, and that period's master movement is geared at it. False once it is there."""
        assert self.link is not None
        m = self.link.position(t)
        target = self.args[0]
        step = self.clutch * (t - self.t_last)
        r = self.ratio_now
        r = min(target, r + step) if target > r else max(target, r - step)
        k = self.link.units / self.base_units
        self.p0 = (self.p0[0] + r * k * (m - self.m0),)
        self.m0, self.t_last = m, t
        self.ratio_now, self.scale = r, r * k
        return r != target

    def link_done(self, t: float) -> bool:
        """CAMBOX / MOVELINK: one servo period at instant ``t`` (:class:`LinkRun`); True when
        the move has ended."""
        if self.done_pos is not None or self.run is None:
            return False
        return self.run.tick(t)

    def continue_from(self, prev: LinkedMove) -> None:
        """Started in the servo period ``prev`` ended by its link distance: count the link
        movement from where ``prev``'s link distance was complete, so none is lost."""
        assert self.run is not None and prev.run is not None
        self.run.m_last = prev.run.m_end

    def link_shifted(self, offset: float) -> None:
        """DEFPOS / OFFPOS moved the link axis' coordinates by ``offset``."""
        self.m0 += offset
        if self.run is not None:
            self.run.shift_link(offset)

    def shift(self, i: int, offset: float) -> None:
        super().shift(i, offset)
        if self.run is not None:
            self.run.shift_base(offset)
        if self.done_pos is not None:
            self.done_pos += offset

    def finish_at(self, tau: float) -> None:
        """CAMBOX / MOVELINK done ``tau`` after the start: the axis is where the last cycle
        ended."""
        assert self.run is not None
        self.done_pos = self.run.position()
        self.end_pos = (self.done_pos,)
        self.profile = Profile([(0.0, 0.0, 0.0, 0.0, 0.0)], tau, 0.0)

    def cancel_at(self, tau: float, decel: float, sramp_s: float = 0.0) -> None:
        """CANCEL: CAM ramps down at DECEL like a move; a move linked to another axis stops at
        once where it is (``[BK]``: only speed-profiled moves ramp down)."""
        if self.kind == "CAM":
            super().cancel_at(tau, decel, sramp_s)
            return
        self.cancelled = True
        here = self.positions(tau)[0]
        self.done_pos = here
        self.end_pos = (here,)
        self.profile = Profile([(0.0, 0.0, 0.0, 0.0, 0.0)], tau, 0.0)

    def endmove(self, i: int) -> float | None:
        """ENDMOVE during CAM / CAMBOX / CONNECT: the end of the previous move (TJ1P-54,
        TJ2P-56); MOVELINK: its own end."""
        return self.end_pos[0] if self.kind == "MOVELINK" else self.p0[0]

    def remaining(self, tau: float | None) -> float:
        """REMAIN: CAM distance, CAMBOX / MOVELINK link distance still to go (TJ2P-56)."""
        if self.kind == "CAM":
            return super().remaining(tau)
        if self.done_pos is not None or tau is None or self.run is None:
            return 0.0
        return self.run.remain()

    def follows_speed(self) -> bool:
        """Only CAM runs at SPEED; the others follow their link axis."""
        return self.kind == "CAM" and super().follows_speed()


__all__ = ["LINKED", "LinkedMove", "check_linked", "link_axis_of"]
