"""One coordinate system running its rotary program: move planning (lookahead) and execution.

What is modelled (TUM p236, p249-250, p339-341; TSRM p177, p429, p446; PUM p213; spec §0,
§4, §9.1-9.3):

* **Planning at RTIs.** Working through program lines ("calculation") happens only at RTIs.
  On ``R`` the first moves are calculated at the next RTI and motion starts at that RTI
  (I11 = 0: "start as soon as calculated"), or I11 ms after the ``R`` (below).
  Every time a move starts executing it asks for planning of the next move, done at the
  next RTI strictly after the move's start.
* **Depth.** Calculation keeps this many moves calculated beyond the executing one: 2 for
  LINEAR with Isx13 = 0 (and CIRCLE, which runs as LINEAR without segmentation, TSRM p177),
  else 1 (spec §4.2, §9.3: from rest the scan runs through the 3rd move). DWELL, DELAY and
  RAPID count as moves. A line is worked through whole.
* **Breaks.** ``DWELL`` and ``RAPID`` stop lookahead: nothing after them is calculated until
  they are finished (then at the next RTI). With Isx92 = 1 (read at ``R``/``S``) every move
  is such a break: no blending, each move ends in a stop before the next is calculated (the
  Isx81/Isx82 in-position wait and dwell are not modelled). ``DELAY`` is a zero-distance
  move, calculated through and blended like any move.
* **Blending.** Consecutive LINEAR/CIRCLE/DELAY moves blend (:mod:`motionsim.sim.pmac.motion`); the
  next move starts — ``move_start``, its synchronous M writes, the previous ``move_end`` — at
  the start of the blend ramp, on a servo cycle. A DWELL or RAPID is preceded by a stop.
* **Running out** of lines is not an error: when motion has stopped and there is nothing left to
  calculate the program is ``waiting`` (still running); a new line is calculated at the next RTI
  and starts at once, without a new ``R``. With Isx13 = 0 a move that starts executing with no
  next move calculated (and no calculation deadline missed, below) ends in a stop ``[INF]``
  (without segmentation the blend must be known when the move starts); with Isx13 > 0
  (segmentation mode) a move calculated before the current move's deceleration to a stop begins
  is blended in (seed 000 "blend into the new move without stopping"), otherwise it starts from
  rest.
* **The calculation deadline** (TUM p339: "If the program fails to keep ahead, and the time for
  the next move comes without the proper data in place for the trajectory generators, Turbo PMAC
  will abort the program and bring all motors in the coordinate system to a stop"; TUM p236:
  planning only at RTIs, one request per move start). The instant a move's successor is needed
  is its decision point: with Isx13 = 0 the move's start (its blend into the next move is fixed
  then — that is why two moves are calculated ahead, TUM p339) ``[INF]``; with Isx13 > 0 the
  start of its deceleration, Ta/2 before its programmed end. If there is no successor then, the
  move would blend (LINEAR / DELAY), calculation was not stopped on purpose (``Q``, ``S``, a
  DWELL / RAPID / Isx92 break) and the oldest uncalculated rotary line was already in the buffer
  when planning last ran, calculation *fell behind*: **run-time error**. The program aborts at
  that instant exactly as with ``A`` (the ``program`` event carries ``error="run_time_error"``),
  ``??`` word 2 bit 22 is set until the next ``R`` / ``S`` or reset (and motor ``?`` word 1 bit
  14, "data block error"). Nothing calculated is left to discard then (the queue is empty by
  definition); queued synchronous writes are dropped with it. Example: 1 ms moves with I8 = 2
  (RTI every 1.33 ms) abort on the third move; with I8 = 0, or 5 ms moves, planning keeps up. A
  line that arrived *after* the last planning is a run-out (above), not an error.
* **I11** (PSRM I11: "the delay from when the run signal is taken ... and when the first
  programmed move starts"; 0 = as soon as calculated). A sequence starting from rest — ``R``, a
  line arriving while ``waiting``, the end of a lookahead break — has its first move due I11 ms
  later (on a servo cycle). Calculation happens at the next RTI; if that is later than the due
  instant and there are lines to calculate, it is a run-time error at the due instant (the abort
  above, no motion). With nothing to calculate it is a run-out.
* **Assignments.** Plain ``=`` assignments act at calculation (1-2 moves early, so ``M1=1``
  between ``X10`` and ``X20`` fires when the move to X10 starts). Synchronous ones (``==``,
  ``&=``, ``|=``, ``^=``) are evaluated at calculation and written at the start of the next
  move or dwell that actually executes; ones left after the last move are never written.
* **Q** stops calculating: the moves already calculated run, the last ends in a stop, then the
  program is ``stopped``. **A** stops at once: every axis decelerates at the motor abort rate
  Ixx15 (motor 1's, cts/ms², one count = one axis unit ``[INF]``), calculated moves and
  queued synchronous writes are discarded (their lines freed); uncalculated lines stay.
* **S** runs one move, then ``stopped``. **H** (feed hold) takes the time base to 0 like
  ``%0`` and ``R`` brings it back; ``%n`` scales moves (not DWELLs). The time base *slews*:
  Isx94 (``%n``) or Isx95 (``H`` and the ``R`` after it) per servo cycle (TSRM p191;
  :meth:`CoordSystem.set_feed_override`).

Program states (``program`` events): idle → running ⇄ waiting → stopped | aborted; running
again only through ``R``/``S``. The legal transitions are the table ``TRANSITIONS``.
"""

from __future__ import annotations

import math
from collections import deque
from typing import TYPE_CHECKING, Any

from motionsim.sim.pmac import motion
from motionsim.sim.pmac.expressions import pmac_and, pmac_or, pmac_xor
from motionsim.sim.pmac.program import (
    OP_ASSIGN,
    OP_AXISMODE,
    OP_DELAY,
    OP_DWELL,
    OP_MODAL,
    OP_MODE,
    OP_MOVE,
    ProgramLine,
)
from motionsim.sim.pmac.scheduler import Wake, wake_at
from motionsim.sim.pmac.variables import isx, ixx

if TYPE_CHECKING:
    from motionsim.sim.pmac.controller import PmacController
    from motionsim.sim.pmac.rotary import RotaryBuffer

IDLE, RUNNING, WAITING, STOPPED, ABORTED = "idle", "running", "waiting", "stopped", "aborted"

#: Legal program-state transitions.
TRANSITIONS: dict[str, frozenset[str]] = {
    IDLE: frozenset({RUNNING}),
    RUNNING: frozenset({WAITING, STOPPED, ABORTED}),
    WAITING: frozenset({RUNNING, STOPPED, ABORTED}),
    STOPPED: frozenset({RUNNING, ABORTED}),
    ABORTED: frozenset({RUNNING}),
}

#: Synchronous read-modify-write forms.
_BITWISE = {"&=": pmac_and, "|=": pmac_or, "^=": pmac_xor}

_ceil = math.ceil
_floor = math.floor

# Move kinds.
LINEAR, DWELL, DELAY, RAPID = 0, 1, 2, 3


class Move:
    """One calculated move (or dwell / delay) and, once started, its profile times.

    ``prev`` is the move it blended from (kept only while this one executes); the per-axis
    velocities ``v`` are computed on demand (only position queries need them).
    """

    __slots__ = (
        "n", "kind", "tm", "ta", "start", "end", "sync", "prev", "_v",
        "b_start", "b_end", "ta_in", "ta_out", "stopping",
    )  # fmt: skip

    def __init__(
        self,
        n: int,
        kind: int,
        tm: float,
        ta: float,
        start: dict[str, float],
        end: dict[str, float],
        sync: list[tuple[int, str, float]] | None,
    ) -> None:
        self.n = n
        self.kind = kind
        self.tm = tm
        self.ta = ta
        self.ta_in = ta
        self.start = start
        self.end = end
        self.sync = sync
        self.prev: Move | None = None
        self._v: dict[str, float] | None = None
        self.ta_out = 0.0
        self.stopping = False

    @property
    def v(self) -> dict[str, float]:
        """Velocity of each axis between the blend ramps (units/s)."""
        if self._v is None:
            start, end, tm = self.start, self.end, self.tm
            self._v = {a: (end[a] - start.get(a, 0.0)) / tm for a in end} if tm > 0 else {}
        return self._v

    @property
    def v_prev(self) -> dict[str, float]:
        return self.prev.v if self.prev is not None else {}

    @property
    def blends(self) -> bool:
        return self.kind == LINEAR or self.kind == DELAY


class CoordSystem:
    """Coordinate system ``cs`` of a :class:`motionsim.sim.pmac.controller.PmacController`."""

    def __init__(self, ctl: PmacController, cs: int) -> None:
        self.ctl = ctl
        self.cs = cs
        self.vars = ctl.vars
        self.sched = ctl.scheduler
        self._env = ctl.env
        self._period = ctl.scheduler.period_s
        self._emit = ctl.log.emit
        self.rotary: RotaryBuffer | None = None
        self.program: float | None = None  # B{n}; 0 = rotary
        self.state = IDLE
        self.planned: deque[Move] = deque()
        self.current: Move | None = None
        self.sync_pending: list[tuple[int, str, float]] = []
        self.blocked = False
        self.quitting = False
        self.single_step = False
        self._plan_due: float | None = None
        self._plan_wake: Wake | None = None  # the last planning wake-up (re-used, wake_at)
        #: The pending execution wake-up (handoff, decision, stop); cancelled by emptying its
        #: callbacks (SimPy then processes it as a no-op).
        self._pending: Wake | None = None
        self._plan_cb_bound = self._plan_cb
        self._handoff_cb = self._start_next  # the blend into the next move starts
        self._stop_end_cb = self._stop_end
        self._decide_cb = self._decide
        self._abort: tuple[float, float, dict[str, float], dict[str, float]] | None = None
        # Modal program state.
        self.mode = "LINEAR"
        self.time_mode = False
        self.incremental: set[str] = set()
        self._fast = False  # time mode, LINEAR, all axes absolute: the planning short cut
        self.no_blend = False  # Isx92 = 1 at the last R / S: stop and re-plan after each move
        #: ``%`` feedrate override (the CS time base), see :meth:`set_feed_override`.
        self.feed_override = 100.0
        self.calc_pos: dict[str, float] = {}
        self.rest_pos: dict[str, float] = {}
        self._ver = -1
        self._isx13 = 0.0
        self._ta_s = 0.0
        self._ta_prog = 0.0
        self._scale = 1.0
        self._pct_before_hold = 100.0  # the time base of the profile frozen by %0 / H
        #: The commanded ``%`` (the slew's goal; ``R`` after ``H`` returns to it).
        self.commanded_override = 100.0
        self._slew_target = 100.0
        self._slew_ivar = 94  # the slew-rate I-variable in use (Isx94, or Isx95 for H / R)
        self._slew_wake: Wake | None = None
        self._frozen_at = 0.0
        self._held = False
        self._decided: Move | None = None  # segmented mode: the move whose blend is decided
        self._f = 1000.0
        self._isx90 = 1000.0
        self._rti = 3
        self._tm_s = 1.0
        self._i11_s = 0.0
        self._starting = False  # an I11 delay before the first move is running
        #: I11: the instant the first move of the sequence being started is due, and the
        #: wake-up that checks it was calculated by then (:meth:`_arm_i11`).
        self._go_t: float | None = None
        self._i11_wake: Wake | None = None
        #: Why the controller aborted the program by itself, until the next ``R`` / ``S`` or
        #: reset: ``"run_time_error"`` (calculation fell behind) or ``"watchdog"``.
        self.error: str | None = None
        #: The rotary line count when planning last had its chance (see the module docstring).
        self._seen_n = 0

    # -- state ----------------------------------------------------------------------------

    def _set_state(self, state: str, **extra: Any) -> None:
        if state == self.state:
            return
        if state not in TRANSITIONS[self.state]:
            raise AssertionError(f"program state {self.state} -> {state} is not legal")
        self.state = state
        self._emit("program", cs=self.cs, state=state, **extra)

    @property
    def running(self) -> bool:
        """Running in the controller's sense: ``R`` given, not stopped (waiting included)."""
        return self.state == RUNNING or self.state == WAITING

    @property
    def moving(self) -> bool:
        return self.current is not None

    @property
    def run_time_error(self) -> bool:
        """Aborted because calculation fell behind (``??`` word 2 bit 22, motor ``?`` word 1
        bit 14)."""
        return self.error == "run_time_error"

    def _refresh(self) -> None:
        """Re-read the CS I-variables (Isx13, Isx87, Isx88) after any I-variable change."""
        v, cs = self.vars, self.cs
        self._ver = v.version
        self._isx13 = v.I(isx(cs, 13))
        pct = self.feed_override if self.feed_override > 0 else self._pct_before_hold
        self._scale = 100.0 / pct  # time-base stretch: real seconds per program second
        self._ta_prog = motion.accel_time_s(v.I(isx(cs, 87)), v.I(isx(cs, 88)))
        self._ta_s = self._ta_prog * self._scale
        self._f = v.I(isx(cs, 89))
        self._isx90 = v.I(isx(cs, 90))
        self._rti = int(v.I(8)) + 1
        # TM-mode move time, real seconds
        self._tm_s = motion.clamp_move_time(self._f / 1000.0, self._ta_prog) * self._scale
        self._i11_s = max(0.0, v.I(11)) / 1000.0

    def _accel_s(self) -> float:
        if self._ver != self.vars.version:
            self._refresh()
        return self._ta_s

    def _segmented(self) -> bool:
        if self._ver != self.vars.version:
            self._refresh()
        return self._isx13 > 0

    # -- on-line commands -----------------------------------------------------------------

    def run(self, single_step: bool = False) -> None:
        """``R`` / ``S``: start (or resume) calculation at the next RTI; after ``H``, resume."""
        if self._held:
            self._held = False
            self._slew_to(self.commanded_override, 95)  # R after H ramps back at Isx95
        self.single_step = single_step
        self.quitting = False
        self.error = None
        # Isx92 (move blend disable) is read only at R / S (TSRM p190).
        self.no_blend = self.vars.I(isx(self.cs, 92)) == 1
        self._fast = False  # re-derived at the next calculated line
        if self.state != RUNNING and self.state != WAITING:
            self._set_state(RUNNING)
        self._request_plan()
        if self.current is None and not self._starting:
            self._arm_i11()

    def quit(self) -> None:
        """``Q``: finish the calculated moves, calculate nothing more, then ``stopped``."""
        if not self.running:
            return
        self.sync_pending.clear()
        if self.current is None and not self.planned:
            self._plan_due = None
            self._set_state(STOPPED)
            return
        self.quitting = True  # (an I11-delayed start still runs the calculated moves)

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
        wake = self._slew_wake
        if wake is not None and wake.callbacks:
            wake.callbacks.clear()
        self._slew_wake = None
        self._slew_target = target
        self._slew_ivar = ivar
        self._slew_tick(None)

    def _slew_tick(self, _ev: Any) -> None:
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
            t = clock.t(clock.index(self._env._now) + 1)
            self._slew_wake = wake_at(self._env, t, self._slew_tick)

    def _apply_time_base(self, pct: float) -> None:
        """The actual time base becomes ``pct`` now. ``0`` freezes motion where it is; else
        the rest of the executing move is stretched around now (positions stay continuous),
        calculated moves are rescaled, later ones are calculated at the new rate."""
        old = self.feed_override
        if pct == old:
            return
        now = self._env._now
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
        if m.kind == RAPID or m.kind == DWELL:
            self._after(self.sched.servo_at_or_after(m.b_end), self._stop_end_cb)
        elif m.stopping:
            self._after(self.sched.servo_at_or_after(m.b_end + m.ta_out / 2), self._stop_end_cb)
        elif self._segmented() and self._decided is not m:
            self._after(self.sched.servo_at_or_after(m.b_end - m.ta / 2), self._decide_cb)
        elif self.planned:
            nxt = self.planned[0]
            self._after(self.sched.servo_at_or_after(m.b_end - nxt.ta_in / 2), self._handoff_cb)
        else:
            self._decide(None)

    def abort(self, error: str | None = None) -> None:
        """``A``: decelerate every axis now at Ixx15; discard lookahead and sync writes.

        ``error`` names why the controller aborted by itself (``"run_time_error"``); it goes
        into the ``program`` event.
        """
        if not self.running:
            return
        now = self.sched.env.now
        self._plan_due = None
        self._cancel()
        self._starting = False
        self.quitting = False
        self.blocked = False
        self.single_step = False
        self.sync_pending.clear()
        self.planned.clear()
        if error is None:
            self._set_state(ABORTED)
        else:
            self.error = error
            self._set_state(ABORTED, error=error)
        m = self.current
        if m is None:
            if self.rotary is not None:
                self.rotary.free_calculated()
            self.calc_pos = dict(self.rest_pos)
            return
        pos = self.positions(now)
        vel = self._velocities(m, now) if self.feed_override > 0 else {}
        rate = self.vars.I(ixx(1, 15)) * 1e6  # cts/ms² -> units/s²
        vmax = max((abs(v) for v in vel.values()), default=0.0)
        t_stop = vmax / rate if rate > 0 else 0.0
        stop = {a: pos[a] + vel.get(a, 0.0) * t_stop / 2 for a in pos}
        self._abort = (now, t_stop, pos, vel)
        self.calc_pos = dict(stop)
        self._after(self.sched.servo_at_or_after(now + t_stop), lambda _e: self._abort_end(stop))

    def _abort_end(self, stop: dict[str, float]) -> None:
        m = self.current
        if m is None:
            return
        self.current = None
        self._abort = None
        self.rest_pos = stop
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
        wake = self._i11_wake
        if wake is not None and wake.callbacks:
            wake.callbacks.clear()
        self._i11_wake = self._go_t = None
        self._starting = self.quitting = self.blocked = self.single_step = False
        self.sync_pending.clear()
        self.planned.clear()
        self._abort = None
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

    def detach(self) -> None:
        """Forget every scheduled wake-up (the controller is being reset)."""
        self._plan_due = None
        self._cancel()
        wake = self._slew_wake
        if wake is not None and wake.callbacks:
            wake.callbacks.clear()
        self._slew_wake = None
        self.state = IDLE

    # -- lines arriving -------------------------------------------------------------------

    def lines_arrived(self) -> None:
        """New lines in the rotary buffer: plan at the next RTI if calculation wants them."""
        if self._plan_due is not None or self.blocked or self.quitting:
            return
        if self.state != RUNNING and self.state != WAITING:
            return
        if self._ver != self.vars.version:
            self._refresh()
        if len(self.planned) < self._depth():
            self._request_plan()
            if self.current is None and not self.planned and self._i11_s > 0:
                self._arm_i11()

    def _depth(self) -> int:
        """How many moves calculation keeps ready (TUM p339, spec §4.2): 2 beyond the executing
        one with Isx13 = 0 — LINEAR, and CIRCLE, which then runs as LINEAR (TSRM p177) — else
        1; one more from rest, where no move is executing yet. (The caller has refreshed.)"""
        depth = 2 if self._isx13 == 0 and self.mode != "RAPID" else 1
        return depth + 1 if self.current is None else depth

    def _request_plan(self) -> None:
        """Ask for move planning at the next RTI (the first cycle divisible by I8+1 after now)."""
        if self._plan_due is not None:
            return
        if self._ver != self.vars.version:
            self._refresh()
        self._plan_at_rti_after(self._env._now)

    # -- planning (RTI) -------------------------------------------------------------------

    def _plan_cb(self, _ev: Any) -> None:
        due = self._plan_due
        if due is None or due > self._env._now:
            return
        self._plan_due = None
        state = self.state
        if self.blocked or self.quitting or (state != RUNNING and state != WAITING):
            return
        rot = self.rotary
        planned = self.planned
        vars_ = self.vars
        if self._ver != vars_.version:
            self._refresh()
        if self.single_step:
            target = 0 if (self.current is not None or planned) else 1
        else:
            target = self._depth()
        if rot is not None and self.program == 0:
            self._seen_n = rot.n_loaded
            pending = rot.pending
            while pending and len(planned) < target and not self.blocked:
                simple = pending[0][1].simple
                if simple is not None and self._fast and self._ver == vars_.version:
                    n = rot.take_simple()
                    # Short cut for the streamed line: one LINEAR move, constant ABS values, TM.
                    start = self.calc_pos
                    end = start.copy()
                    for axis, value in simple:
                        if axis not in start:
                            start[axis] = 0.0
                        end[axis] = value
                    move = Move(n, LINEAR, self._tm_s, self._ta_s, start, end, None)
                    self.calc_pos = end
                    if self.sync_pending:
                        move.sync = self.sync_pending
                        self.sync_pending = []
                    planned.append(move)
                else:
                    n, line = rot.take()  # type: ignore[misc]
                    self._calculate(n, line)
                    self._fast = (
                        self.time_mode
                        and self.mode == "LINEAR"
                        and not self.incremental
                        and not self.no_blend
                    )
                    rot.line_calculated(n)
        if self.current is None and not self._starting and self.feed_override > 0:
            if planned:
                if self.state == WAITING:
                    self._set_state(RUNNING)
                if self._i11_s > 0:
                    # I11: the calculation delay before a sequence starts from rest.
                    self._starting = True
                    now = self._env._now
                    t = self._go_t
                    if t is None:
                        t = self.sched.servo_at_or_after(now + self._i11_s)
                    self._after(t if t > now else now, self._delayed_start)
                else:
                    self._start_next()
            elif self.state == RUNNING:
                self._set_state(WAITING)

    def _arm_i11(self) -> None:
        """A sequence is to start from rest now (``R``, a line arriving while ``waiting``, the
        end of a lookahead break): with I11 > 0 its first move is due I11 ms from now, on a
        servo cycle, and must be calculated by then (PSRM I11; TUM p339)."""
        wake = self._i11_wake
        if wake is not None and wake.callbacks:
            wake.callbacks.clear()
        self._i11_wake = None
        if self._ver != self.vars.version:
            self._refresh()
        if self._i11_s <= 0:
            self._go_t = None
            return
        t = self._go_t = self.sched.servo_at_or_after(self._env._now + self._i11_s)
        # created after the planning request: planning at this same instant is in time
        self._i11_wake = Wake(self._env, t, self._i11_deadline)

    def _i11_deadline(self, _ev: Any) -> None:
        """The I11 time is up: the first move must be calculated now. Nothing calculated with
        lines waiting to be (not a run-out, not stopped) is a run-time error."""
        self._i11_wake = None
        if self.current is not None or self.planned or not self.running:
            return
        rot = self.rotary
        if self.blocked or self.quitting or rot is None or not rot.pending:
            return
        self.abort("run_time_error")

    def _delayed_start(self, _ev: Any) -> None:
        self._starting = False
        self._go_t = None
        if self.current is None and self.planned and self.feed_override > 0:
            self._start_next()

    def _calculate(self, n: int, line: ProgramLine) -> None:
        """Work through one line: assignments, modal settings, its move."""
        vars_ = self.vars
        cs = self.cs
        for op in line.ops:
            code = op[0]
            if code == OP_MOVE:
                self._plan_move(n, op[1], op[2])
            elif code == OP_ASSIGN:
                _, kind, idx, aop, val = op
                k = int(idx.const if idx.const is not None else idx.fn(vars_, cs))
                value = val.const if val.const is not None else val.fn(vars_, cs)
                if aop == "=":
                    vars_.write(kind, k, value, cs)
                else:
                    self.sync_pending.append((k, aop, value))
            elif code == OP_MODAL:
                name, expr = op[1], op[2]
                value = expr(vars_, cs)
                if name == "TA":
                    vars_.write("I", isx(cs, 87), value)
                elif name == "TS":
                    vars_.write("I", isx(cs, 88), value)
                else:
                    vars_.write("I", isx(cs, 89), value)
                    self.time_mode = name == "TM"
            elif code == OP_MODE:
                self.mode = op[1]
            elif code == OP_AXISMODE:
                axes = op[2] or tuple("XYZABCUVW")
                if op[1]:
                    self.incremental.update(axes)
                else:
                    self.incremental.difference_update(axes)
            elif code == OP_DWELL:
                ms = max(0.0, op[1](vars_, cs))
                self._append(Move(n, DWELL, ms / 1000.0, 0.0, self.calc_pos, self.calc_pos, None))
                self.blocked = True
            elif code == OP_DELAY:
                ta = self._accel_s()
                tm = motion.clamp_move_time(max(0.0, op[1](vars_, cs)) / 1000.0, self._ta_prog)
                tm *= self._scale
                self._append(Move(n, DELAY, tm, ta, self.calc_pos, self.calc_pos, None))
                if self.no_blend:
                    self.blocked = True

    def _append(self, move: Move) -> None:
        if self.sync_pending:
            move.sync = self.sync_pending
            self.sync_pending = []
        self.planned.append(move)

    def _plan_move(self, n: int, axes: tuple, vectors: tuple) -> None:
        vars_, cs = self.vars, self.cs
        start = self.calc_pos
        end = start.copy()
        inc = self.incremental
        for axis, expr in axes:
            v = expr.const if expr.const is not None else expr.fn(vars_, cs)
            if axis not in start:
                start[axis] = 0.0
            end[axis] = start[axis] + v if axis in inc else v
        if self._ver != vars_.version:
            self._refresh()
        ta = self._ta_s
        mode = self.mode
        if mode == "RAPID":
            speed = vars_.I(ixx(1, 22)) * 1000.0  # cts/ms -> units/s
            dist = max((abs(end[a] - start[a]) for a in end), default=0.0)
            t = (dist / speed if speed > 0 else 0.0) + vars_.I(ixx(1, 21)) / 1000.0
            t = max(t, motion.MIN_MOVE_S) * self._scale
            move = Move(n, RAPID, t, 0.0, start, end, None)
            self.calc_pos = end
            self._append(move)
            self.blocked = True
            return
        if self.time_mode:
            t = self._f / 1000.0
        else:
            if mode != "LINEAR" and vectors and self._segmented():
                vec = dict(vectors)
                ij = (
                    vec["I"](vars_, cs) if "I" in vec else 0.0,
                    vec["J"](vars_, cs) if "J" in vec else 0.0,
                )
                radius = vec["R"](vars_, cs) if "R" in vec else None
                dist = motion.arc_length(
                    start, end, None if radius else ij, radius, mode == "CIRCLE1"
                )
            else:
                dist = motion.vector_distance({a: end[a] - start[a] for a in end})
            t = motion.feed_time_s(dist, self._f, self._isx90)
        t = motion.clamp_move_time(t, self._ta_prog) * self._scale
        move = Move(n, LINEAR, t, ta, start, end, None)
        self.calc_pos = end
        if self.sync_pending:
            move.sync = self.sync_pending
            self.sync_pending = []
        self.planned.append(move)
        if self.no_blend:
            self.blocked = True  # Isx92 = 1: every move is a lookahead break

    # -- execution ------------------------------------------------------------------------

    def _start_next(self, _ev: Any = None) -> None:
        """The next calculated move starts executing now: blended from the executing move
        (the hand-off wake-up), or from rest.

        The previous move ends (``move_end``) and this one starts (``move_start``, after its
        synchronous M writes) at the same instant; the words of lines executed are freed; the
        "plan the next move" flag is served at the next RTI; then what ends this move is
        scheduled — the hand-off into the next calculated move, the segmented-mode decision
        point, or the stop. This is also the per-line hot path of a stream.
        """
        m = self.planned.popleft()
        prev = self.current
        t = self._env._now
        emit = self._emit
        cs = self.cs
        n = m.n
        if prev is not None:
            emit("move_end", cs=cs, n=prev.n)
            prev.prev = None  # keep only one step of history
            m.prev = prev
            b = prev.b_end
        else:
            b = t + m.ta / 2
        m.b_start = b
        rot = self.rotary
        if rot is not None:
            calc = rot.calculated
            if calc and calc[0][0] < n:
                rot.free_through(n - 1)
        if m.sync:
            for k, aop, value in m.sync:
                self._sync_write(k, aop, value)
        emit("move_start", cs=cs, n=n)
        m.b_end = b + m.tm
        self.current = m
        if self._ver != self.vars.version:
            self._refresh()
        p = self._period
        if self._plan_due is None and not (self.blocked or self.quitting or self.single_step):
            # = self._plan_at_rti_after(t), written out (the per-line path)
            r = self._rti
            k = _floor(t / p + 1e-6) + 1
            tp = self._plan_due = -(-k // r) * r * p
            self._plan_wake = wake_at(self._env, tp, self._plan_cb_bound, self._plan_wake)
        kind = m.kind
        if kind in (DWELL, RAPID):
            m.b_start = t
            m.b_end = t + m.tm
            m.stopping = True
            self._after(self.sched.servo_at_or_after(m.b_end), self._stop_end_cb)
            return
        if self._isx13 > 0:
            self._after(self.sched.servo_at_or_after(m.b_end - m.ta / 2), self._decide_cb)
            return
        planned = self.planned
        if planned and not self.single_step:
            nxt = planned[0]
            if nxt.kind == LINEAR or nxt.kind == DELAY:
                # = self._blend_into(m, nxt), written out (the per-line path)
                lim = 2 * (m.tm - m.ta_in / 2)
                ta_n = nxt.ta if nxt.ta <= lim else max(0.0, lim)
                nxt.ta_in = ta_n
                pend = self._pending
                if pend is not None and pend.callbacks:
                    pend.callbacks.clear()
                th = _ceil((m.b_end - ta_n / 2) / p - 1e-6) * p
                self._pending = wake_at(self._env, th if th > t else t, self._handoff_cb, pend)
                return
        self._decide(None)

    def _plan_at_rti_after(self, t: float) -> None:
        """Set the "plan the next move" flag: planning at the first RTI strictly after ``t``
        (cycles divisible by I8+1; TUM p236)."""
        tp = self._plan_due = self.sched.next_rti_after(t)
        self._plan_wake = wake_at(self._env, tp, self._plan_cb_bound, self._plan_wake)

    def _blend_into(self, m: Move, nxt: Move) -> None:
        """``m`` blends into ``nxt``: ``nxt``'s ramp is clipped to ``2·(TM − Ta/2)`` of ``m``
        (spec §9.1) and the hand-off is at the start of that ramp, on a servo cycle."""
        lim = 2 * (m.tm - m.ta_in / 2)
        ta_n = nxt.ta if nxt.ta <= lim else max(0.0, lim)
        nxt.ta_in = ta_n
        self._after(self.sched.servo_at_or_after(m.b_end - ta_n / 2), self._handoff_cb)

    def _after(self, t: float, fn: Any) -> None:
        """Call ``fn(event)`` at ``t``, superseding (cancelling) the pending wake-up."""
        pend = self._pending
        if pend is not None and pend.callbacks:
            pend.callbacks.clear()
        env = self._env
        self._pending = wake_at(env, t if t > env._now else env._now, fn, pend)

    def _cancel(self) -> None:
        """Cancel the pending execution wake-up, if it has not happened yet."""
        pend = self._pending
        if pend is not None:
            if pend.callbacks:
                pend.callbacks.clear()
            self._pending = None

    def _decide(self, _ev: Any) -> None:
        """Blend into the next calculated move, or plan the stop at the end of this one."""
        m = self.current
        assert m is not None
        self._decided = m
        planned = self.planned
        if planned and not self.single_step:
            nxt = planned[0]
            if (nxt.kind == LINEAR or nxt.kind == DELAY) and (m.kind == LINEAR or m.kind == DELAY):
                self._blend_into(m, nxt)
                return
        elif self._fell_behind(m):
            self.abort("run_time_error")
            return
        m.stopping = True
        m.ta_out = self._accel_s() if m.kind != DWELL else 0.0
        self._after(self.sched.servo_at_or_after(m.b_end + m.ta_out / 2), self._stop_end_cb)

    def _fell_behind(self, m: Move) -> bool:
        """No successor is calculated at ``m``'s decision point: is it a calculation deadline
        missed (run-time error, TUM p339) rather than a run-out (PUM p213)?

        Missed when ``m`` would blend, calculation was not stopped on purpose (Q, S, a DWELL /
        RAPID / Isx92 break), and the oldest uncalculated line was already in the buffer when
        planning last ran — so planning had its chance and did not get that far.
        """
        if not m.blends or self.quitting or self.single_step or self.blocked:
            return False
        rot = self.rotary
        if rot is None or not rot.pending or self.state != RUNNING:
            return False
        return rot.pending[0][0] <= self._seen_n

    def _stop_end(self, _ev: Any) -> None:
        m = self.current
        assert m is not None
        self._emit("move_end", cs=self.cs, n=m.n)
        self.current = None
        m.prev = None
        self.rest_pos = dict(m.end)
        if m.kind == DWELL or m.kind == RAPID or self.no_blend:
            self.blocked = False
        self._motion_stopped()

    def _motion_stopped(self) -> None:
        """Motion has come to rest: start what is calculated, or stop / wait."""
        rot = self.rotary
        if self.planned:
            if self.feed_override > 0:
                self._start_next()
            return
        if rot is not None:
            rot.free_calculated()
        if self.quitting or self.single_step:
            self.quitting = False
            self.single_step = False
            self.sync_pending.clear()
            self._set_state(STOPPED)
        elif self.state == RUNNING:
            if rot is not None and rot.pending and not self.blocked:
                self._request_plan()
                self._arm_i11()
            else:
                self._set_state(WAITING)

    def _sync_write(self, k: int, aop: str, value: float) -> None:
        vars_ = self.vars
        if aop == "==":
            vars_.write("M", k, value, self.cs, sync=True)
            return
        old = vars_.read("M", k, self.cs)
        vars_.write("M", k, _BITWISE[aop](old, value), self.cs, sync=True)

    # -- positions --------------------------------------------------------------------------

    def _velocities(self, m: Move, t: float) -> dict[str, float]:
        out: dict[str, float] = {}
        for a in m.end:
            out[a] = motion.velocity_at(
                t, m.v.get(a, 0.0), m.b_start, m.ta_in, m.v_prev.get(a, 0.0),
                m.b_end if m.stopping else None, m.ta_out,
            )  # fmt: skip
        return out

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
            t0, t_stop, pos, vel = self._abort
            tau = min(max(t - t0, 0.0), t_stop)
            if t_stop <= 0:
                return dict(pos)
            return {a: pos[a] + vel.get(a, 0.0) * (tau - tau * tau / (2 * t_stop)) for a in pos}
        if m.kind == DWELL:
            return dict(m.end)
        out: dict[str, float] = {}
        for a in m.end:
            out[a] = motion.position_at(
                t, m.start.get(a, 0.0), m.v.get(a, 0.0), m.b_start, m.ta_in,
                m.v_prev.get(a, 0.0), m.b_end if m.stopping else None, m.ta_out,
            )  # fmt: skip
        return out

    # -- status ---------------------------------------------------------------------------

    def status_words(self) -> tuple[int, int, int]:
        """The three 24-bit words of ``??`` (TSRM p284-287; spec §3, §9.4)."""
        w1 = w2 = 0
        if self.running:
            w1 |= 1 << 0
            if not self.single_step and not self.no_blend:
                w1 |= 1 << 4
        if self.single_step:
            w1 |= 1 << 1
        if self.current is not None and self.current.blends:
            w1 |= 1 << 2
        if self.time_mode:
            w1 |= 1 << 3
        mode_bits = {"LINEAR": 0, "RAPID": 0b10, "CIRCLE1": 0b01, "CIRCLE2": 0b11}[self.mode]
        w2 |= mode_bits
        if self.current is not None and self.current.kind == DWELL:
            w2 |= 1 << 12
        if self.rotary is not None and self.rotary.full:
            w2 |= 1 << 16
        if self.current is None:
            w2 |= 1 << 17
        if self.run_time_error:
            w2 |= 1 << 22
        return w1, w2, 0

    def to_dict(self) -> dict[str, Any]:
        """The API's ``program`` object."""
        out: dict[str, Any] = {"state": self.state}
        if self.error is not None:
            out["error"] = self.error
        if self.current is not None:
            out["line"] = self.current.n
        return out


__all__ = ["TRANSITIONS", "CoordSystem", "Move"]
