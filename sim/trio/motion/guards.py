"""What stops a move before its own end: the software limits and the following-error trip.

:class:`AxisGuards` is the part of :class:`motionsim.sim.trio.motion.buffers.MotionBuffers`
that watches the executing moves for them (a mixin: it acts on the buffers' moves, ends and
servo periods):

* software limits (:mod:`motionsim.sim.trio.motion.limits`, TRM p. 8-177): when a move starts,
  is re-planned or shifted, or FS_LIMIT / RS_LIMIT are written, the servo period at which its
  path first takes an axis to a limit is worked out and scheduled; at that period the move
  ramps down at DECEL (FASTDEC when set) and ends cancelled, with a ``soft_limit`` event
  (``axis``, ``limit``, ``mtype``). Linked moves, whose path follows another axis, are looked
  at every servo period;
* the following error (:meth:`motionsim.sim.trio.motion.axis.Axis.following_error`): an axis
  with an ``fe_lag`` is looked at every servo period while it moves; with SERVO on, an FE
  beyond FE_LIMIT trips it (TRM p. 8-177, SERVO: AXISSTATUS bit 8, SERVO off, the axis
  stopped) with a ``following_error`` event (``axis``, ``fe``);
* either is an error condition on the axis: ``on_axis_error(axis)`` lets the controller raise
  the motion error ERRORMASK asks for (:mod:`motionsim.sim.trio.card.system`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from ...events import EventLog
from ...timing import ServoClock
from ..card.axis_status import FE_LIMIT_BIT
from . import limits
from .axis import Axis
from .datum import DatumMove
from .linked import LinkedMove
from .moves import Move
from .profile import Profile

#: The deceleration of a move stopped where it is (the drive is off): within one period.
AT_ONCE = 1e15


class AxisGuards:
    """Software-limit and following-error watch of the executing moves (module docstring)."""

    axes: list[Axis]
    clock: ServoClock
    env: Any
    log: EventLog
    _active: dict[Move, None]
    _links: dict[Any, None]

    def _init_guards(self) -> None:
        #: software limits: the servo period a move's path first passes a limit at, with the
        #: profile that was computed from (a re-planned move is armed again), the axis and
        #: the limit; linked moves are watched every period (their last base position)
        self._limit_at: dict[int, list[tuple[Move, Profile, int, str]]] = {}
        self._limit_watch: dict[Move, float] = {}
        #: axes with a following-error model (``fe_lag``) and a move: FE looked at each period
        self._fe_watch: set[int] = set()
        #: an error condition arose on an axis (the controller raises the motion error)
        self.on_axis_error: Callable[[int], None] | None = None

    if TYPE_CHECKING:  # MotionBuffers provides them
        def _reschedule_end(self, m: Move, now_k: int) -> None: ...
        def _tick_at(self, k: int) -> None: ...
        def _kick(self) -> None: ...

    def _guards_busy(self) -> bool:
        """Whether a linked move or an axis' following error is looked at every period."""
        return bool(self._limit_watch or self._fe_watch)

    def _guards_due(self, k: int) -> None:
        """Servo period ``k``, before the moves advance: the limit stops and FE trips due."""
        if self._limit_at or self._limit_watch:
            self._limits_due(k)
        if self._fe_watch:
            self._fe_due(k)

    def _guard_move(self, m: Move, k: int, axes: list[Axis]) -> None:
        """``m`` started at period ``k`` on ``axes`` (its axes, in order): arm its limits,
        watch the FE of its lagging axes."""
        self._arm_limits(m, k)
        for ax in axes:
            if ax.fe_lag > 0.0:
                self._fe_watch.add(ax.n)

    def limits_changed(self, axis: int) -> None:
        """FS_LIMIT / RS_LIMIT of ``axis`` written: look at its executing move again."""
        m = self.axes[axis].mtype
        if m is not None and m.start_tick is not None and m in self._active:
            self._arm_limits(m, max(self.clock.index(self.env.now), m.start_tick))

    def _arm_limits(self, m: Move, k: int) -> None:
        """Schedule (or, when it is due, make) the limit stop of ``m`` as of period ``k``."""
        if m.cancelled or m.profile is None or m.start_tick is None:
            return
        if type(m) is not Move:
            if isinstance(m, LinkedMove):
                base = self.axes[m.axes[0]]
                self._limit_watch[m] = base.own_position(self.clock.t(k))
            return  # a DATUM sequence is not stopped by the software limits
        if limits.ends_inside(m, self.axes):
            return
        prof = m.profile
        tau = self.clock.t(k) - m.t_start
        hit = limits.first_hit(m, [self.axes[a] for a in m.axes],
                               m.s_off + prof.s(tau))
        if hit is None:
            return
        s_hit, axis, which = hit
        k_hit = max(k, self.clock.at_or_after(m.t_start + prof.time_at(s_hit - m.s_off)))
        if k_hit <= k:
            self._limit_stop(m, k, axis, which)
            return
        self._limit_at.setdefault(k_hit, []).append((m, prof, axis, which))
        self._tick_at(k_hit)

    def _limit_stop(self, m: Move, k: int, axis: int, which: str) -> None:
        """``axis`` of ``m`` hit ``which`` limit at period ``k``: the move ramps down at the
        base axis' DECEL (FASTDEC when above 0, ``[BK]``) and ends cancelled."""
        assert m.profile is not None
        base = self.axes[m.axes[0]]
        fastdec = base.stored.values["FASTDEC"]
        decel = fastdec if fastdec > 0.0 else base.decel
        m.cancel_at(self.clock.t(k) - m.t_start, decel, base.sramp / 1000.0)
        if not isinstance(m, DatumMove):
            self._links.pop(m, None)  # type: ignore[call-overload]
        self._limit_watch.pop(m, None)
        self._reschedule_end(m, k)
        self.log.emit("soft_limit", axis=axis, limit=which, mtype=m.mtype)
        if self.on_axis_error is not None:
            self.on_axis_error(axis)

    def watch_fe(self, axis: int) -> None:
        """``fe_lag`` of ``axis`` written: a move already running on it is watched too."""
        ax = self.axes[axis]
        if ax.fe_lag > 0.0 and ax.mtype is not None:
            self._fe_watch.add(axis)
            self._kick()

    def _fe_due(self, k: int) -> None:
        """Period ``k``: the following error of each watched axis against its FE_LIMIT."""
        t = self.clock.t(k)
        for n in sorted(self._fe_watch):
            ax = self.axes[n]
            fe = ax.following_error(t)
            st = ax.stored.values
            if st["SERVO"] and abs(fe) > st["FE_LIMIT"]:
                self._fe_trip(ax, k, fe)
            if ax.mtype is None or (ax.mtype.cancelled and fe == 0.0):
                self._fe_watch.discard(n)

    def _fe_trip(self, ax: Axis, k: int, fe: float) -> None:
        """The following error of ``ax`` exceeded FE_LIMIT with SERVO on (M216-367, SERVO: "the
        following error bit is set in the AXISSTATUS register, the enable relay is forced OFF
        and the servo is set OFF"): AXISSTATUS bit 8 latches, SERVO reads OFF, FE_LATCH keeps
        the error ``[BK]``, and the axis' executing move stops where it is (the drive is off,
        ``[INF]``); then the motion error of ERRORMASK (:mod:`motionsim.sim.trio.card.system`)."""
        st = ax.stored.values
        st["SERVO"] = 0.0
        st["FE_LATCH"] = fe
        ax.error_bits |= FE_LIMIT_BIT
        m = ax.mtype
        if m is not None and m.profile is not None and not m.cancelled:
            m.cancel_at(self.clock.t(k) - m.t_start, AT_ONCE)
            self._links.pop(m, None)  # type: ignore[call-overload]
            self._limit_watch.pop(m, None)
            self._reschedule_end(m, k)
        self.log.emit("following_error", axis=ax.n, fe=fe)
        if self.on_axis_error is not None:
            self.on_axis_error(ax.n)

    def _limits_due(self, k: int) -> None:
        """Period ``k``: the scheduled limit stops whose move runs on as computed, and one look
        at each linked move."""
        for m, prof, axis, which in self._limit_at.pop(k, ()):
            if m in self._active and not m.cancelled and m.profile is prof:
                self._limit_stop(m, k, axis, which)
        if self._limit_watch:
            t = self.clock.t(k)
            for m, prev in list(self._limit_watch.items()):
                if m not in self._active or m.cancelled:
                    del self._limit_watch[m]
                    continue
                ax = self.axes[m.axes[0]]
                here = m.positions(t - m.t_start)[0]
                lo, hi = limits.limits_of(ax)
                which = limits.outward(here, prev, lo, hi)
                if which is not None:
                    self._limit_stop(m, k, ax.n, which)
                else:
                    self._limit_watch[m] = here


__all__ = ["AT_ONCE", "FE_LIMIT_BIT", "AxisGuards"]
