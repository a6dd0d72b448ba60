"""Execution of calculated moves: blending, stops, the calculation deadline, Q / A / S, kill.

Modelled (TUM p339-341, p250; PUM p213; spec §9.1-9.3):

* **Blending.** Consecutive moves whose profiles blend (LINEAR / CIRCLE / DELAY) are joined
  (:mod:`motionsim.sim.pmac.modes.linear`); the next move starts — ``move_start``, the
  previous ``move_end`` — at the start of the blend ramp, on a servo cycle; its synchronous
  M writes go to :mod:`.sync_queue` (performed at the first RTI at or after then, TUM p250).
  A lookahead break (DWELL, RAPID, PSET) is preceded by a stop. PVT and SPLINE moves
  abut without a ramp; a spline move ending with only the waiting point after it ends the
  series there (that point's move to rest), unless calculation fell behind (below).
* **Running out.** With Isx13 = 0 a move that starts executing with no next move calculated
  (and no calculation deadline missed, below) ends in a stop ``[INF]`` (without segmentation
  the blend must be known when the move starts); with Isx13 > 0 (segmentation mode) a move
  calculated before the current move's deceleration to a stop begins is blended in (seed 000
  "blend into the new move without stopping"), otherwise it starts from rest. The blend
  ramp (clipped to ``2·(TM − Ta/2)``) is centred on the programmed point, so a next move
  calculated in time with a ramp longer than the current move's deceleration is decided
  at the start of that ramp; one calculated after that instant has its ramp shortened to
  start at once ``[INF]``: the commanded path never jumps.
* **The calculation deadline** (TUM p339: "If the program fails to keep ahead, and the time
  for the next move comes without the proper data in place for the trajectory generators,
  Turbo PMAC will abort the program and bring all motors in the coordinate system to a
  stop"; TUM p236: planning only at RTIs, one request per move start). The instant a move's
  successor is needed is its decision point: with Isx13 = 0 the move's start (its blend into
  the next move is fixed then — that is why two moves are calculated ahead, TUM p339)
  ``[INF]``; with Isx13 > 0 the start of its deceleration, Ta/2 before its programmed end.
  If there is no successor then, the move would blend, calculation was not stopped on
  purpose (``Q``, ``S``, a DWELL / RAPID / Isx92 break) and the oldest uncalculated rotary
  line was already in the buffer when planning last ran, calculation *fell behind*:
  **run-time error**. The program aborts at that instant exactly as with ``A`` (the
  ``program`` event carries ``error="run_time_error"``), ``??`` word 2 bit 22 is set until
  the next ``R`` / ``S`` or reset (and motor ``?`` word 1 bit 14, "data block error").
  Queued synchronous writes are dropped with it. Example: 1 ms moves with I8 = 2 (RTI every
  1.33 ms) abort on the third move; with I8 = 0, or 5 ms moves, planning keeps up. A line
  that arrived *after* the last planning is a run-out, not an error.
* **Q** stops calculating: the moves already calculated run, the last ends in a stop, then
  the program is ``stopped``. **A** stops at once: each axis decelerates at its motor's abort
  rate Ixx15, not on the path (abort_stop.py), calculated moves and queued synchronous
  writes are discarded (their lines freed); uncalculated lines stay.
  **S** runs one move, then ``stopped``.
"""

from __future__ import annotations

import functools
from typing import TYPE_CHECKING

from ...simpy_adapter import cancel, supersede
from ..buffers.motion import position_at
from ..card.variables import ixx
from ..modes import BLENDS, DELAY, DWELL, LINEAR, PROFILES, SPLINE, Move
from ..modes import linear as linear_mode
from ..modes.home import HomeMove
from ..modes.pset import PsetMove
from ..tasks.scheduler import first_rti_after, servo_at_or_after, wake_at
from . import abort_stop
from .state import CoordState
from .states import ABORTED, RUNNING, STOPPED
from .sync_queue import segment_start

if TYPE_CHECKING:
    from ...simpy_adapter import Callback

#: The fields of ``move_start`` / ``move_end`` (:meth:`motionsim.sim.events.EventLog.emit_row`).
_CS_N = ("cs", "n")

#: Move kinds cut into Isx13 segments in segmentation mode (LINEAR and CIRCLE, DELAY as a
#: zero-distance LINEAR move ``[INF]``; TSRM p177).
_SEGMENTED = frozenset({LINEAR, DELAY})


class Execution(CoordState):
    """The execution part of :class:`~motionsim.sim.pmac.lookahead.CoordSystem`: the state it
    reads and writes is declared in :class:`.state.CoordState`."""

    if TYPE_CHECKING:  # what execution calls in the planning part (:mod:`.planning`)

        def _plan_cb(self, _ev: object) -> None: ...
        def _request_plan(self) -> None: ...
        def _arm_i11(self) -> None: ...
        def _spline_close(self) -> None: ...

    # -- execution ------------------------------------------------------------------------

    def _start_next(self, _ev: object = None) -> None:
        """The next calculated move starts executing now: blended from the executing move
        (the hand-off wake-up), or from rest.

        The previous move ends (``move_end``) and this one starts (``move_start``; its
        synchronous M writes are handed to the queue, performed first if this is their RTI) at
        the same instant; the words of lines executed are freed; the
        "plan the next move" flag is served at the next RTI; then what ends this move is
        scheduled — the hand-off into the next calculated move, the segmented-mode decision
        point, or the stop. This is also the per-line hot path of a stream.
        """
        m = self.planned.popleft()
        if m.kind == DWELL and type(m) is not Move:
            if type(m) is PsetMove:
                self._pset(m)
                return
            if type(m) is HomeMove:
                self._home(m)
                return
        prev = self.current
        env = self._env
        t = env._now
        row = self._row
        cs = self.cs
        n = m.n
        if prev is not None:
            row("move_end", _CS_N, (cs, prev.n))
            prev.prev = None  # keep only one step of history
            m.prev = prev
            b = prev.b_end
        else:
            b = t + m.ta / 2
        m.b_start = b
        rot = self.rotary if self.program == 0 else None  # (a fixed program frees nothing)
        if rot is not None:
            calc = rot.calculated
            if calc and calc[0][0] < n:
                # the words of the lines before this move's are free (the per-line path)
                while calc and calc[0][0] < n:
                    rot.used_words -= calc.popleft()[1]
        if prev is None:
            self._seg_t0 = t  # a sequence from rest: its segments start now
        if m.sync:
            self.sync_queue.started(m.sync, self._sync_ready(m, t))
        row("move_start", _CS_N, (cs, n))
        m.b_end = b + m.tm
        if self.on_move_start is not None:  # a kinematic CS (sim.pmac.kinematics)
            self.on_move_start(m, t)  # before m is current: the path so far is prev's
        self.current = m
        if self._ver != self.vars.version:
            self._refresh()
        p = self._period
        if self._plan_due is None and not (self.blocked or self.quitting or self.single_step):
            # = self._plan_at_rti_after(t) with the cached I8 + 1 (the per-line path)
            tp = self._plan_due = first_rti_after(t, p, self._rti)
            self._plan_wake = wake_at(env, tp, self._plan_fn, self._plan_wake)
        prof = PROFILES[m.kind]
        if prof.breaks:
            m.b_start = t
            m.b_end = t + m.tm
            m.stopping = True
            self._after(self.sched.servo_at_or_after(m.b_end), self._stop_end)
            return
        if self._isx13 > 0:
            self._after(self.sched.servo_at_or_after(self._decision_at(m)), self._decide)
            return
        planned = self.planned
        if planned and not self.single_step:
            nxt = planned[0]
            if BLENDS[m.kind][nxt.kind]:
                self._blend_into(m, nxt)
                return
        if prof.decide_at_end:  # the next move is needed only at this one's end (PVT)
            # (= self._after(self.sched.servo_at_or_after(...), self._decide): per PVT line)
            now = env._now
            th = servo_at_or_after(m.b_end - m.ta / 2, p)
            self._pending = supersede(env, th if th > now else now, self._decide_fn,
                                      self._pending)
            return
        self._decide(None)

    def _pset(self, m: PsetMove) -> None:
        """A PSET's turn (motion is at rest): the axes it names take their new values now,
        the motors stay where they are (their axis offsets move), lookahead resumes — the next
        move is calculated at the next RTI, then the I11 delay (TUM p341; :mod:`..modes.pset`).
        """
        old = self.rest_pos
        for axis, value in m.values.items():
            d = value - old.get(axis, 0.0)
            if d:
                for motor, scale in self.motors_of(axis):
                    mo = self.ctl.motor(motor)
                    mo.profile = mo.profile.shifted(-d * scale)
        self.rest_pos = {**old, **m.values}
        self._emit("pset", cs=self.cs, n=m.n, positions=dict(m.values))
        self.blocked = False
        self._motion_stopped()

    def _home(self, m: HomeMove) -> None:
        """A ``HOME{list}``'s turn (motion is at rest): the listed motors start their home
        searches; the program goes on when the last has ended (:mod:`..modes.home`)."""
        ctl = self.ctl
        waiting: list[int] = []
        for n in m.motors:
            mo = ctl.motor(n)
            if m.zero:
                mo.home_zero()
            else:
                mo.home()
                waiting.append(n)
        self._homing = waiting
        if not waiting:
            self._homed(m.motors)
            return
        for n in waiting:
            ctl.motor(n).when_stopped.append(functools.partial(self._home_ended, n, m.motors))

    def _home_ended(self, n: int, motors: tuple[int, ...]) -> None:
        """Motor ``n``'s home search of a program ``HOME`` (of ``motors``) has ended."""
        if n in self._homing:
            self._homing.remove(n)
            if not self._homing and self.running:
                self._homed(motors)

    def _homed(self, motors: tuple[int, ...]) -> None:
        """Every motor of the program's ``HOME`` is home: the axes of this CS's homed motors
        take their home displacement (the motors do not move), lookahead resumes."""
        now = self._env._now
        ctl = self.ctl
        pos = dict(self.rest_pos)
        for motor in motors:
            have = ctl._motor_axis(motor)
            if have is None or have[0] != self.cs or not have[2]:
                continue
            mo = ctl.motor(motor)
            d = mo.profile.position(now)
            if d:
                mo.profile = mo.profile.shifted(-d)
                pos[have[1]] = pos.get(have[1], 0.0) + d / have[2]
        self.rest_pos = pos
        self.calc_pos = dict(pos)
        self.blocked = False
        self._motion_stopped()

    def _decision_at(self, m: Move) -> float:
        """Segmentation mode: where ``m``'s blend or stop is decided, the start of its
        deceleration, Ta/2 before its end -- earlier when the stop Ixx17 allows is longer
        (the special lookahead plans the deceleration ahead, TSRM p98, p181), and earlier
        when the next move is already calculated with a longer blend ramp, which is centred
        on the programmed point too (spec §9.1) ``[INF]``: deciding early is harmless, the
        blend (clipped then, :meth:`_blend_into`) is the same."""
        ta = self._stop_ta(m)
        planned = self.planned
        if planned and not self.single_step and BLENDS[m.kind][planned[0].kind]:
            ta = max(ta, planned[0].ta)
        return m.b_end - ta / 2

    def _stop_ta(self, m: Move) -> float:
        """``m``'s own deceleration ramp: its TA, or the longer stop Ixx17 allows."""
        return max(m.ta, m.ta_stop * self._scale) if m.ta_stop else m.ta

    def _successor_planned(self) -> None:
        """Segmentation mode: the move after the executing one (``current``, not yet decided)
        has just been calculated: the decision moves to where its blend ramp begins, if that
        is before the decision point set at the move's start (re-armed at the same instant
        otherwise)."""
        m = self.current
        assert m is not None
        if self._decided is m or m.stopping or PROFILES[m.kind].breaks or self.feed_override == 0:
            return
        self._after(self.sched.servo_at_or_after(self._decision_at(m)), self._decide)

    def _blend_into(self, m: Move, nxt: Move) -> None:
        """``m`` blends into ``nxt``: ``nxt``'s ramp is clipped to ``2·(TM − Ta/2)`` of ``m``
        (spec §9.1) and the hand-off is at the start of that ramp, on a servo cycle. A ramp
        cannot begin before the blend is decided (segmentation mode decides at ``m``'s
        deceleration point) -- more than the servo cycle its hand-off is rounded to: a
        longer one (its move calculated late) is shortened to the time left to ``m``'s
        programmed end, so the blend starts now ``[INF]``."""
        now, p = self._env._now, self._period
        lim = 2 * (m.tm - m.ta_in / 2)
        late = 2 * (m.b_end - now + p)
        if late < lim:
            lim = late
        ta_n = nxt.ta if nxt.ta <= lim else max(0.0, lim)
        nxt.ta_in = ta_n
        # = self._after(self.sched.servo_at_or_after(...), self._start_next) without the two
        # calls: this is once per streamed line
        th = servo_at_or_after(m.b_end - ta_n / 2, p)
        pend = self._pending
        self._pending = supersede(self._env, th if th > now else now, self._start_fn, pend)

    def _after(self, t: float, fn: Callback) -> None:
        """Call ``fn(event)`` at ``t`` (now if that is past), superseding (cancelling) the
        pending execution wake-up."""
        now = self._env._now
        self._pending = supersede(self._env, t if t > now else now, fn, self._pending)

    def _cancel(self) -> None:
        """Cancel the pending execution wake-up, if it has not happened yet."""
        cancel(self._pending)
        self._pending = None

    def _decide(self, _ev: object) -> None:
        """Blend into the next calculated move, or plan the stop at the end of this one."""
        m = self.current
        assert m is not None
        self._decided = m
        planned = self.planned
        if not planned and self.spline is not None and m.kind == SPLINE and not self.single_step:
            # a spline move's end needs the waiting point's move: fell behind, or the end
            if self._fell_behind(m):
                self.abort("run_time_error")
                return
            self._spline_close()
        if planned and not self.single_step:
            nxt = planned[0]
            if BLENDS[m.kind][nxt.kind]:
                if PROFILES[m.kind].decide_at_end:
                    # no blend ramp (PVT): the decision point is the hand-off itself
                    self._pending = None
                    self._start_next()
                    return
                self._blend_into(m, nxt)
                return
        elif self._fell_behind(m):
            self.abort("run_time_error")
            return
        m.stopping = True
        if PROFILES[m.kind].stop_ramp:
            # the TA / TS in force now, stretched to the stop ramp Ixx17 allows (accel_limit)
            ta = self._accel_s()
            m.ta_out = max(ta, m.ta_stop * self._scale) if m.ta_stop else ta
        else:
            m.ta_out = 0.0
        self._after(self.sched.servo_at_or_after(m.b_end + m.ta_out / 2), self._stop_end)

    def _fell_behind(self, m: Move) -> bool:
        """No successor is calculated at ``m``'s decision point: is it a calculation deadline
        missed (run-time error, TUM p339) rather than a run-out (PUM p213)?

        Missed when ``m`` would blend, calculation was not stopped on purpose (Q, S, a DWELL /
        RAPID / Isx92 break), and the oldest uncalculated line was already in the buffer when
        planning last ran — so planning had its chance and did not get that far.
        """
        if not PROFILES[m.kind].blends or self.quitting or self.single_step or self.blocked:
            return False
        rot = self.lines()
        if rot is None or not rot.pending or self.state != RUNNING:
            return False
        return rot.pending[0][0] <= self._seen_n

    def _stop_end(self, _ev: object) -> None:
        """The executing move (or the break it made) has come to a stop."""
        m = self.current
        assert m is not None
        self._emit("move_end", cs=self.cs, n=m.n)
        self.current = None
        m.prev = None
        self.rest_pos = dict(m.end)
        if PROFILES[m.kind].breaks or self.no_blend or not self.planned:
            # The break this move made (a DWELL / PSET, or Isx92 = 1 then) is over; with
            # nothing calculated after it, also when Isx92 was cleared and R given meanwhile.
            self.blocked = False
        self._motion_stopped()

    def _motion_stopped(self) -> None:
        """Motion has come to rest: start what is calculated, or stop / wait."""
        rot = self.lines()
        if self.planned:
            if self._end_stop:  # ``/``: the calculated moves wait for R / S (CoordSystem)
                self._end_stop = self.quitting = False
                self._set_state(STOPPED)
            elif self.feed_override > 0:
                self._start_next()
            return
        if (
            self.spline is not None
            and self.state == RUNNING
            and not (self.quitting or self.single_step)
            and not (rot is not None and rot.pending and not self.blocked)
        ):
            self._spline_close()  # the waiting spline point has no next one: the series ends
            if self.feed_override > 0:
                self._start_next()
            return
        if rot is not None and self.spline is None:  # (a waiting spline point keeps its words)
            rot.free_calculated()
        if self.quitting or self.single_step:
            self.quitting = self._end_stop = False
            self.single_step = False
            self._set_state(STOPPED)  # leftover synchronous writes stay queued (TUM p250)
        elif self.state == RUNNING:
            if rot is not None and rot.pending and not self.blocked:
                self._request_plan()
                self._arm_i11()
            else:
                self._ran_out()

    def _sync_ready(self, m: Move, t: float) -> float:
        """When ``m``'s synchronous writes may be performed, ``m`` starting at ``t`` (the
        start of its blend): then, or with Isx13 > 0 for a segmented move (LINEAR / CIRCLE /
        DELAY) the first Isx13 segment at or after then (TUM p250; :mod:`.sync_queue`)."""
        if m.kind in _SEGMENTED and self._segmented():
            seg = segment_start(t, self._seg_t0, self._isx13 / 1000.0)
            return self.sched.servo_at_or_after(seg)
        return t

    def abort(self, error: str | None = None) -> None:
        """``A``: decelerate every axis now at Ixx15; discard lookahead and sync writes.

        ``error`` names why the controller aborted by itself (``"run_time_error"``); it goes
        into the ``program`` event.
        """
        self.sync_pending.clear()
        self.sync_queue.discard()
        if not self.running:
            return
        now = self.sched.env.now
        self._plan_due = None
        self._cancel()
        self._starting = False
        self.quitting = self._end_stop = False
        self._homing = []
        self.blocked = False
        self.single_step = False
        self.planned.clear()
        self.spline = None
        if error is None:
            self._set_state(ABORTED)
        else:
            self.error = error
            self._set_state(ABORTED, error=error)
        m = self.current
        if m is None:
            if self.rotary is not None:
                self.rotary.free_calculated()
            self.calc_vel = {}
            self.calc_pos = dict(self.rest_pos)
            return
        pos = self.positions(now)
        vel = self._velocities(m, now) if self.feed_override > 0 else {}
        self._abort = ramp = abort_stop.plan(now, pos, vel, self._abort_rate)
        stop = ramp.end()
        self.calc_vel = {}
        self.calc_pos = dict(stop)
        self._after(self.sched.servo_at_or_after(now + ramp.t_stop), self._abort_end)

    def _abort_rate(self, axis: str) -> float:
        """The abort deceleration of ``axis`` in units/s²: Ixx15 (cts/ms²) of its motors in
        this CS over their counts per unit, the lowest; motor 1's at 1 count/unit without a
        motor ``[INF]`` (abort_stop.py)."""
        rates = [
            self.vars.I(ixx(n, 15)) * 1e6 / abs(scale) for n, scale in self.motors_of(axis) if scale
        ]
        return min(rates) if rates else self.vars.I(ixx(1, 15)) * 1e6

    def _abort_end(self, _ev: object) -> None:
        """Every axis has come to rest after ``A`` (:attr:`_abort`, the stop under way)."""
        m, ramp = self.current, self._abort
        if m is None or ramp is None:
            return
        self.current = None
        self._abort = None
        self.rest_pos = ramp.end()
        self._emit("move_end", cs=self.cs, n=m.n)
        self._motion_stopped()

    def kill(self, error: str) -> None:
        """Motors killed (watchdog trip; TSRM p57, TUM p215): amplifiers off, no deceleration.

        The commanded positions freeze where they are at this instant: the executing move (or
        an ``A`` deceleration) ends now (``move_end``), calculated moves and queued synchronous
        writes are dropped with their words, a running program is ``aborted`` with ``error``,
        and nothing is left scheduled for this CS.
        """
        now = self._env._now
        m = self.current
        was_running = self.running
        if m is not None:
            self.rest_pos = self.positions(now)
        self._plan_due = None
        self._cancel()
        cancel(self._i11_wake)
        self._i11_wake = self._go_t = None
        self._starting = self.quitting = self.blocked = self.single_step = False
        self._end_stop = False
        self._homing = []
        self.sync_pending.clear()
        self.sync_queue.discard()
        self.planned.clear()
        self.spline = None
        self._abort = None
        self.calc_vel = {}
        self.calc_pos = dict(self.rest_pos)
        if self.rotary is not None:
            self.rotary.free_calculated()
        if m is not None:
            self.current = None
            m.prev = None
            self._emit("move_end", cs=self.cs, n=m.n)
        if was_running:
            self.error = error
            self._set_state(ABORTED, error=error)

    # -- positions --------------------------------------------------------------------------

    def _velocities(self, m: Move, t: float) -> dict[str, float]:
        return PROFILES[m.kind].velocities(m, t)

    def positions(self, t: float | None = None) -> dict[str, float]:
        """Commanded axis positions at ``t`` (default now), from the move profile."""
        if t is None:
            t = self.sched.env.now
        if self.feed_override == 0 and t > self._frozen_at:
            t = self._frozen_at
        m = self.current
        if m is None:
            return dict(self.rest_pos)
        if self._abort is not None:
            return self._abort.positions(t)
        return PROFILES[m.kind].positions(m, t)

    def axis_position_spec(self, axis: str) -> AxisSpec | None:
        """What ``positions(t).get(axis, 0.0)`` is as a function of ``t`` alone while nothing
        about the motion changes, as numbers copied out of the present state
        (:func:`axis_position_at` evaluates it): data gathering
        (:mod:`motionsim.sim.pmac.tasks.gather_readers`) uses it for the servo cycles between
        two events. A float for a CS at rest (or an axis the move does not name); the
        arguments of the :func:`~motionsim.sim.pmac.buffers.motion.position_at` call
        :class:`~motionsim.sim.pmac.modes.linear.BlendedProfile` makes for a blended LINEAR
        move without arc offsets; None for anything else (other modes, an ``A`` stop, a
        frozen time base), which the caller reads through :meth:`positions` instead."""
        if self.feed_override == 0:
            return None
        m = self.current
        if m is None:
            return self.rest_pos.get(axis, 0.0)
        if self._abort is not None or PROFILES[m.kind] is not linear_mode.PROFILE:
            return None
        prev = m.prev
        if m.arc is not None or (prev is not None and prev.arc is not None):
            return None
        if axis not in m.end:
            return 0.0
        return (m.start.get(axis, 0.0), m.v.get(axis, 0.0), m.b_start, m.ta_in,
                m.v_prev.get(axis, 0.0), m.b_end if m.stopping else None, m.ta_out)


    def axis_spec_key(self) -> tuple[object, ...]:
        """Everything :meth:`axis_position_spec` reads that may change while this CS runs,
        compared by value or identity: equal keys give equal specs, so a caller may keep the
        specs it has (data gathering does at every event). A move's start / end points,
        kind and arc never change once it is calculated."""
        m = self.current
        if m is None:
            return (self.feed_override, None, self.rest_pos)
        prev = m.prev
        return (self.feed_override, m, self._abort, m.b_start, m.b_end, m.ta_in, m.ta_out,
                m.stopping, m.tm, m._v, prev, None if prev is None else prev._v,
                None if prev is None else prev.tm)


#: :meth:`Execution.axis_position_spec`: a constant position, or ``position_at``'s arguments.
AxisSpec = float | tuple[float, float, float, float, float, float | None, float]


def axis_position_at(spec: AxisSpec, t: float) -> float:
    """The axis position at ``t`` an :meth:`Execution.axis_position_spec` describes."""
    if isinstance(spec, float):
        return spec
    return position_at(t, *spec)


__all__ = ["AxisSpec", "Execution", "axis_position_at"]
