"""The coordinate system's time base: feedrate override ``%`` and feed hold ``H``.

``H`` (feed hold) takes the time base to 0 like ``%0`` and ``R`` brings it back; ``%n``
scales moves, DELAYs and RAPIDs (not DWELLs, nor RTI planning). The time base *slews*: Isx94
(``%n``) or Isx95 (``H`` and the ``R`` after it) per servo cycle (TSRM p191, p429). A change
stretches the rest of the executing move around the present instant (positions stay
continuous) and rescales the calculated moves; the execution part then re-aims its pending
wake-up (:meth:`TimeBase._reschedule`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ...simpy_adapter import cancel
from ..card.variables import isx
from ..modes import DWELL, PROFILES, Move
from ..tasks.scheduler import wake_at
from .state import CoordState
from .states import RUNNING, WAITING

if TYPE_CHECKING:
    from ...simpy_adapter import Callback


class TimeBase(CoordState):
    """The time-base part of :class:`~motionsim.sim.pmac.lookahead.CoordSystem`: the state it
    reads and writes is declared in :class:`.state.CoordState`."""

    if TYPE_CHECKING:  # what the time base calls in the execution part (:mod:`.execution`)

        def _start_next(self, _ev: object = None) -> None: ...
        def _decide(self, _ev: object) -> None: ...
        def _stop_end(self, _ev: object) -> None: ...
        def _after(self, t: float, fn: Callback) -> None: ...
        def _cancel(self) -> None: ...
        def _decision_at(self, m: Move) -> float: ...

    def hold(self) -> None:
        """``H``: feed hold — like ``%0`` but the time base slews at Isx95 (TSRM p191, PSRM
        Ix95: "equivalent to a %0 command except that it uses Ix95"); ``R`` ramps back to the
        commanded ``%`` at Isx95."""
        self._held = True
        self._slew_to(0.0, 95)

    def set_feed_override(self, percent: float) -> None:
        """``%n``: command the CS time base to ``n`` %; the actual value (``feed_override``,
        what ``%`` reports) slews there at Isx94 (TSRM p191). Moves, DELAYs and RAPIDs follow
        the actual time base; DWELLs and RTI planning stay in real time (TSRM p429).

        ``%n`` ends a feed hold (the new value is the goal) ``[INF]``.
        """
        pct = max(0.0, float(percent))
        self.commanded_override = pct
        self._held = False
        self._slew_to(pct, 94)

    def _slew_to(self, target: float, ivar: int) -> None:
        """Slew the actual time base to ``target`` at Isx``ivar`` (94 or 95).

        The rate is in 2**-23 ms of time base per servo cycle; 100 % is one servo period of
        program time per cycle, so one cycle changes the value by ``100 · rate / (period_ms ·
        2**23)`` % (1644 at 442 µs: 0.044 %, 0 → 100 % in ≈ 1 s). The first step is taken at
        the command's own servo cycle, one more at each following cycle; the time base is
        constant within a cycle, so the motion profile is stretched piecewise (exactly what
        the controller integrates). A rate large enough to cover the change in one step (the
        maximum 8 388 607 is ≈ 226 % per cycle at 442 µs) makes the change instant.
        Rate 0: the time base does not move at all ``[INF]`` — the manual gives 0 no special
        meaning, and a slew rate of 0 per cycle never reaches the new value (``%`` keeps
        reporting the old one). The rate is read at every step, so a new Isx94 / Isx95 acts
        on a slew in progress; a rate of 0 ends it, and the time base stays where it is until
        the next ``%`` / ``H`` / ``R`` (not re-armed by the I-variable write) ``[INF]``.
        """
        cancel(self._slew_wake)
        self._slew_wake = None
        self._slew_target = target
        self._slew_ivar = ivar
        self._slew_tick(None)

    def _slew_tick(self, _ev: object) -> None:
        """One servo cycle of a time-base slew."""
        self._slew_wake = None
        rate = max(0.0, self.vars.I(isx(self.cs, self._slew_ivar)))
        step = 100.0 * rate / (self._period * 1000.0 * 2**23)
        cur, target = self.feed_override, self._slew_target
        if step <= 0 or cur == target:
            return  # rate 0: the time base stays where it is
        new = cur + step if target > cur else cur - step
        if abs(target - cur) <= step:
            new = target  # the last step lands on the commanded value
        self._apply_time_base(new)
        if new != target:
            clock = self.sched.clock
            t = clock.t(clock.after(self._env.now))
            self._slew_wake = wake_at(self._env, t, self._slew_tick)

    def _apply_time_base(self, pct: float) -> None:
        """The actual time base becomes ``pct`` now. ``0`` freezes motion where it is; else
        the rest of the executing move is stretched around now (positions stay continuous),
        calculated moves are rescaled, later ones are calculated at the new rate."""
        old = self.feed_override
        if pct == old:
            return
        now = self._env.now
        m = self.current
        moving = m is not None and self._abort is None and m.kind != DWELL
        if old == 0:
            old_eff = self._pct_before_hold
            if moving:
                self._shift(m, now - self._frozen_at)  # type: ignore[arg-type]
        else:
            old_eff = old
        self.feed_override = pct
        self._ver = -1  # re-read the scale
        if pct == 0:
            self._pct_before_hold = old_eff
            self._frozen_at = now
            if moving:
                self._cancel()  # nothing happens while frozen
            return
        k = old_eff / pct  # new stretch / old stretch
        for p in self.planned:
            if p.kind == DWELL:
                continue  # DWELL is real time, never scaled by % (TSRM p429)
            p.tm *= k
            p.ta *= k
            p.ta_in *= k
            p._v = None
        if moving:
            self._stretch(m, now, k)  # type: ignore[arg-type]
            self._reschedule()
        elif m is None and self.planned and not self._starting and self.running:
            if self.state == WAITING:
                self._set_state(RUNNING)  # moves calculated while frozen at %0 start now
            self._start_next()

    @staticmethod
    def _shift(m: Move, dt: float) -> None:
        m.b_start += dt
        m.b_end += dt

    @staticmethod
    def _stretch(m: Move, t: float, k: float) -> None:
        """Stretch the executing move's remaining profile by ``k`` around ``t``."""
        m.b_start = t + (m.b_start - t) * k
        m.b_end = t + (m.b_end - t) * k
        m.tm *= k
        m.ta *= k
        m.ta_in *= k
        m.ta_out *= k
        m._v = None
        prev = m.prev
        if prev is not None:
            prev.tm *= k
            prev._v = None

    def _reschedule(self) -> None:
        """Re-aim the pending execution wake-up after the time base changed."""
        m = self.current
        if m is None:
            return
        if PROFILES[m.kind].breaks:
            self._after(self.sched.servo_at_or_after(m.b_end), self._stop_end)
        elif m.stopping:
            self._after(self.sched.servo_at_or_after(m.b_end + m.ta_out / 2), self._stop_end)
        elif self._segmented() and self._decided is not m:
            self._after(self.sched.servo_at_or_after(self._decision_at(m)), self._decide)
        elif PROFILES[m.kind].decide_at_end and self._decided is not m:
            self._after(self.sched.servo_at_or_after(m.b_end - m.ta / 2), self._decide)
        elif self.planned:
            nxt = self.planned[0]
            self._after(self.sched.servo_at_or_after(m.b_end - nxt.ta_in / 2), self._start_next)
        else:
            self._decide(None)


__all__ = ["TimeBase"]
