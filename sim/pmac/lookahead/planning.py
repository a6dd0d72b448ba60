"""Move planning ("calculation") of a coordinate system: working through program lines at RTIs.

Modelled (TUM p236, p249-250, p339-341; TSRM p177, p190; PSRM I11; PUM p213; spec §4, §9.3):

* **Planning at RTIs.** Working through program lines happens only at RTIs. On ``R`` the
  first moves are calculated at the next RTI and motion starts at that RTI (I11 = 0: "start
  as soon as calculated"), or I11 ms after the ``R`` (below). Every time a move starts
  executing it asks for planning of the next move, done at the next RTI strictly after the
  move's start.
* **Depth.** Calculation keeps this many moves calculated beyond the executing one: 2 for
  LINEAR with Isx13 = 0 (and CIRCLE, which runs as LINEAR without segmentation, TSRM p177),
  else 1 (spec §4.2, §9.3: from rest the scan runs through the 3rd move). DWELL, DELAY and
  RAPID count as moves. A line is worked through whole. SPLINE1 / SPLINE2 keep 2 as well, but
  a spline move is calculated only once the next point is read (:mod:`..modes.spline`), so
  calculation reads one line further; the open series ends at another mode's move, a DWELL /
  DELAY, or, with nothing more to read, from rest here or at the executing move's end.
* **Breaks.** ``DWELL``, ``RAPID`` and ``PSET`` (:mod:`motionsim.sim.pmac.modes.pset`) stop
  lookahead: nothing after them is calculated until
  they are finished (then at the next RTI). With Isx92 = 1 (read at ``R``/``S``) every move
  is such a break: no blending, each move ends in a stop before the next is calculated (the
  Isx81/Isx82 in-position wait and dwell are not modelled). ``DELAY`` is a zero-distance
  move, calculated through and blended like any move.
* **Running out** of lines is not an error: when motion has stopped and there is nothing left
  to calculate the program is ``waiting`` (still running); a new line is calculated at the
  next RTI and starts at once, without a new ``R``.
* **I11** (PSRM I11: "the delay from when the run signal is taken ... and when the first
  programmed move starts"; 0 = as soon as calculated). A sequence starting from rest — ``R``,
  a line arriving while ``waiting``, the end of a lookahead break — has its first move due
  I11 ms later (on a servo cycle). Calculation happens at the next RTI; if that is later than
  the due instant and there are lines to calculate, it is a run-time error at the due instant
  (the abort of :mod:`.execution`, no motion). With nothing to calculate it is a run-out.
* **Assignments.** Plain ``=`` assignments act at calculation (1-2 moves early, so ``M1=1``
  between ``X10`` and ``X20`` fires when the move to X10 starts). Synchronous ones (``==``,
  ``&=``, ``|=``, ``^=``) are evaluated at calculation and go with the next move or dwell
  calculated; they are written at the first RTI at or after it starts executing
  (:mod:`.sync_queue`). Ones left after the last move wait for the next move calculated
  (after more lines, or a new ``R``) unless ``MFLUSH`` or ``A`` removes them (TUM p250).

Each move's time and profile come from its mode's module (:mod:`motionsim.sim.pmac.modes`);
this part only decides *when* lines are worked through and keeps the modal state.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ...simpy_adapter import cancel, pending
from ..buffers.program import (
    OP_ASSIGN,
    OP_AXISMODE,
    OP_DELAY,
    OP_DWELL,
    OP_FRAX,
    OP_HOME,
    OP_MODAL,
    OP_MODE,
    OP_MOVE,
    OP_PSET,
    OP_SEND,
    ProgramLine,
)
from ..card.variables import isx
from ..modes import (
    LINEAR,
    PROFILES,
    Move,
    RunTimeError,
    dwell,
    linear,
    pset,
    pvt,
    rapid,
    spline,
)
from ..modes.home import HomeMove
from ..tasks.scheduler import Wake, wake_at
from .state import SPLINES, CoordState
from .states import RUNNING, STOPPED, WAITING

if TYPE_CHECKING:
    from ...simpy_adapter import Callback
    from ..buffers.programs import ProgramRun
    from ..buffers.rotary import RotaryBuffer
    from ..language.expressions import Expr

    #: A move op's axis words, vector words or velocity words: ``((letter, expr), ...)``
    #: (:data:`motionsim.sim.pmac.buffers.program.OP_MOVE`).
    AxisWords = tuple[tuple[str, Expr], ...]

#: The planning short cuts for a line of constant axis words (``_fast``).
_FAST_LINEAR, _FAST_PVT = 1, 2


class Planning(CoordState):
    """The planning part of :class:`~motionsim.sim.pmac.lookahead.CoordSystem`: the state it
    reads and writes is declared in :class:`.state.CoordState`."""

    if TYPE_CHECKING:  # what planning calls in the execution part (:mod:`.execution`)

        def abort(self, error: str | None = None) -> None: ...
        def _start_next(self, _ev: object = None) -> None: ...
        def _after(self, t: float, fn: Callback) -> None: ...
        def _successor_planned(self) -> None: ...

    # -- lines arriving -------------------------------------------------------------------

    def lines_arrived(self) -> None:
        """New lines in the rotary buffer: plan at the next RTI if calculation wants them."""
        if self.blocked or self.quitting or (self.state != RUNNING and self.state != WAITING):
            return
        if self._plan_due is not None:
            if self.current is None and not self.planned and not pending(self._i11_wake):
                # From rest with calculation already due (asked for by the last move's start)
                # and no I11 delay running: the sequence starts at this line, its delay too.
                self._arm_i11()
            return
        if self._ver != self.vars.version:
            self._refresh()
        if len(self.planned) < self._depth_at[self.current is None] or (
            self._la_s > 0 and self._short_of_horizon()
        ):
            self._request_plan()
            if self.current is None and not self.planned:
                self._arm_i11()  # (also at I11 = 0: a delay armed under an earlier I11 goes)

    def _short_of_horizon(self) -> bool:
        """The special lookahead is active (Isx13 > 0, ``DEFINE LOOKAHEAD``, Isx20 > 0) and
        the calculated moves cover less than its horizon, Isx20 segments of Isx13 ms (TSRM
        p181, p308: the CS looks Isx20 segments ahead) ``[INF]``: counted in move time."""
        la = self._la_s
        if la <= 0 or self.single_step:
            return False
        return sum(m.tm for m in self.planned) < la * self._scale

    def _request_plan(self) -> None:
        """Ask for move planning at the next RTI (the first cycle divisible by I8+1 after now)."""
        if self._plan_due is not None:
            return
        if self._ver != self.vars.version:
            self._refresh()
        self._plan_at_rti_after(self._env._now)

    def _plan_at_rti_after(self, t: float) -> None:
        """Set the "plan the next move" flag: planning at the first RTI strictly after ``t``
        (cycles divisible by I8+1; TUM p236)."""
        tp = self._plan_due = self.sched.next_rti_after(t)
        self._plan_wake = wake_at(self._env, tp, self._plan_fn, self._plan_wake)

    # -- planning (RTI) -------------------------------------------------------------------

    def _plan_cb(self, _ev: object) -> None:
        """The planning pass at an RTI (the wake-up set by :meth:`_plan_at_rti_after`): work
        through lines until the lookahead depth is reached, then start a sequence from rest
        if motion is at rest and something was calculated."""
        due = self._plan_due
        if due is None or due > self._env._now:
            return
        self._plan_due = None
        state = self.state
        if self.blocked or self.quitting or (state != RUNNING and state != WAITING):
            return
        rot = self.rotary if self.program == 0 else self.fixed  # = self.lines() (hot path)
        planned = self.planned
        vars_ = self.vars
        if self._ver != vars_.version:
            self._refresh()
        stepping = self.single_step
        # a step calculates one move; otherwise the depth
        target = (
            (0 if self.current is not None or planned else 1)
            if stepping
            else self._depth_at[self.current is None]
        )
        if rot is not None:
            self._seen_n = rot.n_loaded
            pending = rot.pending
            # a fixed program: moves say which program (a CALLed one) their line is in, for PE
            run = self.fixed if self.program != 0 else None
            # (_short_of_horizon is False unless the special lookahead is active: _la_s > 0)
            lines_left = self.step_lines if stepping else None
            move: Move
            while (
                pending
                and (
                    (len(planned) < target if lines_left is None else lines_left > 0)
                    or (self._la_s > 0 and self._short_of_horizon())
                    or (stepping and rot.in_block)  # S runs on to BLOCKSTOP (TSRM p182)
                )
                and not self.blocked
            ):
                if lines_left is not None:  # Isx53 = 1: a step executes one line
                    lines_left -= 1
                    self.step_lines = lines_left
                line = pending[0][1]
                simple = line.simple
                fast = self._fast
                if fast == _FAST_PVT and line.simple_pvt is not None and self._ver == vars_.version:
                    n = rot.take_simple()
                    move, self.calc_vel = pvt.plan_constant(
                        n, self.calc_pos, line.simple_pvt, self.calc_vel,
                        self._pvt_t, self._pvt_to_s, self._scale,
                    )  # fmt: skip
                    self.calc_pos = move.end
                    if self.sync_pending:
                        self._append(move)  # with the writes calculated before it
                    else:
                        planned.append(move)
                    if run is not None:
                        move.prog = run.taken_prog
                elif simple is not None and fast == _FAST_LINEAR and self._ver == vars_.version:
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
                        self._append(move)  # with the writes calculated before it
                    else:
                        planned.append(move)
                    if run is not None:
                        move.prog = run.taken_prog
                else:
                    taken = rot.take()
                    if taken is None:
                        break  # control flow ends this pass (rot.interrupt says why)
                    n, line = taken
                    before = len(planned)
                    try:
                        self._calculate(n, line)
                    except RunTimeError:
                        rot.line_calculated(n)
                        self.abort("run_time_error")
                        return
                    if run is not None:
                        for k in range(1, len(planned) - before + 1):
                            planned[-k].prog = run.taken_prog
                    self._fast = self._fast_kind()
                    rot.line_calculated(n)
            if rot.interrupt is not None and self._flow_interrupt(rot):
                return
            if lines_left == 0 and self.current is None and not planned:
                self._step_done()  # the stepped line held no move: the step ends here
                return
            if planned and self.current is not None and self._isx13 > 0:
                self._successor_planned()  # (a longer blend ramp is decided earlier)
        if self.current is None and not planned and self.spline is not None:
            self._spline_close()  # from rest with no next point: the series is this much
        if self.current is None and not self._starting and self.feed_override > 0:
            if planned:
                if self.state == WAITING:
                    self._set_state(RUNNING)
                if self._i11_s > 0 and type(planned[0]) is not pset.PsetMove:
                    # I11: the calculation delay before a sequence starts from rest (a PSET
                    # is no move: it runs now, and the I11 delay follows it).
                    self._starting = True
                    now = self._env._now
                    t = self._go_t
                    if t is None:
                        t = self.sched.servo_at_or_after(now + self._i11_s)
                    self._after(t if t > now else now, self._delayed_start)
                else:
                    self._start_next()
            elif self.state == RUNNING:
                self._ran_out()

    def _step_done(self) -> None:
        """A step (Isx53 = 1) whose one line calculated no move: the program stops there,
        ready for the next ``S`` or ``R`` ``[INF]``."""
        self.single_step = False
        self.step_lines = None
        self._set_state(STOPPED)

    def _flow_interrupt(self, rot: RotaryBuffer | ProgramRun) -> bool:
        """A fixed program's control flow ended the pass (:mod:`..buffers.programs`): a
        run-time error aborts; ``WAIT`` or the double-jump-back rule with a move calculated
        or executing lets that move come to a stop before calculation resumes (TUM p341;
        ``[INF]`` for WAIT), and from rest calculation resumes at the next RTI. True when
        the planning pass is over."""
        why, rot.interrupt = rot.interrupt, None
        if why == "error":
            self.abort("run_time_error")
            return True
        if why == "suspend" or why == "wait":
            if self.current is None and not self.planned:
                self._plan_at_rti_after(self._env._now)
                return True
            self.blocked = True
        return False

    def _fast_kind(self) -> int:
        """Which planning short cut the next constant line may take: ``_FAST_LINEAR`` (time
        mode, LINEAR, all axes absolute), ``_FAST_PVT`` (PVT, all axes absolute, a valid
        segment time) or none. Not while a spline series is open (the next move closes it
        first) and not for LINEAR while PVT end velocities are kept (the first LINEAR move
        clears them): the full path does both."""
        if self.incremental or self.no_blend or self.spline is not None:
            return 0
        if self.mode == "LINEAR" and self.time_mode and not self.ctl.motors and not self.calc_vel:
            return _FAST_LINEAR  # (with motors assigned, Ixx16 needs the full path)
        if self.mode == "PVT" and self._pvt_t > 0:
            return _FAST_PVT
        return 0

    def _arm_i11(self) -> None:
        """A sequence is to start from rest now (``R``, a line arriving while ``waiting``, the
        end of a lookahead break): with I11 > 0 its first move is due I11 ms from now, on a
        servo cycle, and must be calculated by then (PSRM I11; TUM p339)."""
        cancel(self._i11_wake)
        self._i11_wake = None
        if self._ver != self.vars.version:
            self._refresh()
        if self._i11_s <= 0:
            self._go_t = None
            return
        t = self._go_t = self.sched.servo_at_or_after(self._env._now + self._i11_s)
        # created after the planning request: planning at this same instant is in time
        self._i11_wake = Wake(self._env, t, self._i11_deadline)

    def _i11_deadline(self, _ev: object) -> None:
        """The I11 time is up: the first move must be calculated now. Nothing calculated with
        lines waiting to be (not a run-out, not stopped) is a run-time error."""
        self._i11_wake = None
        if self.current is not None or self.planned or not self.running:
            return
        rot = self.lines()
        if self.blocked or self.quitting or rot is None or not rot.pending:
            return
        self.abort("run_time_error")

    def _delayed_start(self, _ev: object) -> None:
        """The I11 delay is over: the sequence's first move starts."""
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
                self._plan_move(n, op[1], op[2], op[3])
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
                    if name == "F":  # TSRM p193: a larger F runs at Isx98 (0: no limit)
                        cap = vars_.I(isx(cs, 98))
                        if 0 < cap < value:
                            value = cap
                    vars_.write("I", isx(cs, 89), value)
                    self.time_mode = name == "TM"
            elif code == OP_MODE:
                self.mode = op[1]
            elif code == OP_AXISMODE:
                axes = op[2] or tuple("XYZABCUVW")
                if "R" in axes:  # INC(R) / ABS(R): the circle centre vectors (TSRM p442)
                    self.abs_radius = not op[1]
                    axes = tuple(a for a in axes if a != "R")
                if op[1]:
                    self.incremental.update(axes)
                else:
                    self.incremental.difference_update(axes)
            elif code == OP_DWELL:
                self._spline_close()
                self.calc_vel = {}
                self._lin_w = None
                self._append(dwell.plan_dwell(n, op[1](vars_, cs), self.calc_pos))
                self.blocked = True
            elif code == OP_FRAX:
                self.frax = op[1]
            elif code == OP_SEND:  # when the line is calculated, ahead of its move's run
                self.ctl.log.emit("program_send", cs=cs, line=n, port=op[1] or "host",
                                  text=op[2])
                self.ctl.send_message(f"cs{cs}", op[1], op[2])
            elif code == OP_PSET:
                self._spline_close()
                self._lin_w = None  # the move after PSET starts from rest (no corner)
                values = {
                    a: e.const if e.const is not None else e.fn(vars_, cs) for a, e in op[1]
                }
                self.calc_vel = {}
                move = pset.plan(n, self.calc_pos, values)
                self.calc_pos = move.end.copy()
                self.planned.append(move)  # no synchronous writes: they go with a move
                self.blocked = True  # nothing after PSET is calculated until it has run
            elif code == OP_HOME:  # a lookahead break (modes.home)
                self._spline_close()
                self.calc_vel = {}
                self._lin_w = None
                self.planned.append(HomeMove(n, self.calc_pos, op[1], op[2]))
                self.blocked = True
            elif code == OP_DELAY:
                self._spline_close()
                self.calc_vel = {}
                self._lin_w = None
                if self._ver != vars_.version:
                    self._refresh()
                self._append(dwell.plan_delay(self, n, op[1](vars_, cs), self.calc_pos))
                if self.no_blend:
                    self.blocked = True

    def _append(self, move: Move) -> None:
        """A calculated move joins ``planned``, carrying the synchronous writes calculated
        since the last one (TUM p250: they go with the next move calculated)."""
        if self.sync_pending:
            move.sync = self.sync_pending
            self.sync_pending = []
        self.planned.append(move)

    def _plan_move(
        self, n: int, axes: AxisWords, vectors: AxisWords, velocities: AxisWords
    ) -> None:
        """A move line: the end point from the axis words (INC / ABS), then the move of the
        current mode; RAPID (and every move with Isx92 = 1) is a lookahead break. A PVT
        segment starts at the previous segment's end velocities (``calc_vel``)."""
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
        mode = self.mode
        if mode in SPLINES:
            self._plan_spline(n, start, end, velocities)
            return
        self._spline_close()
        if mode == "PVT":
            v_end = {a: 0.0 for a in end}
            for axis, expr in velocities:
                v_end[axis] = expr.const if expr.const is not None else expr.fn(vars_, cs)
            move: Move = pvt.plan(self, n, start, end, self.calc_vel, v_end)
            self.calc_vel = v_end
        else:
            self.calc_vel = {}
            if mode == "RAPID":
                move = rapid.plan(self, n, start, end)
            else:
                # Ixx17 at the corner: from the previous calculated LINEAR move, unless this
                # one starts from rest (nothing executing or calculated, or Isx92 = 1).
                from_rest = self.no_blend or (self.current is None and not self.planned)
                move = linear.plan(self, n, start, end, vectors, None if from_rest else self._lin_w)
        self._lin_w = (
            {a: v * self._scale for a, v in move.v.items()}  # program time
            if move.kind == LINEAR and self.ctl.motors
            else None
        )
        self.calc_pos = end
        self._append(move)
        if self.no_blend or PROFILES[move.kind].breaks:
            self.blocked = True  # Isx92 = 1: every move is a lookahead break

    def _plan_spline(
        self, n: int, start: dict[str, float], end: dict[str, float], velocities: AxisWords
    ) -> None:
        """A SPLINE1 / SPLINE2 point: the previous point's move is calculated now (it needed
        this one); this point's move waits for the next point, or for the end of the series
        (:meth:`_spline_close`). A velocity word in SPLINE mode is a run-time error ``[INF]``.
        The point's synchronous writes wait with it."""
        if velocities:
            raise RunTimeError("SPLINE: an axis word with a velocity")
        moves, self.spline = spline.plan(self, self.spline, n, start, end, self.sync_pending)
        self.sync_pending = []
        self.planned.extend(moves)
        self.calc_vel = {}
        self._lin_w = None  # a LINEAR move after the series starts from its rest (no corner)
        self.calc_pos = end
        if self.no_blend:
            self._spline_close()  # Isx92 = 1: every point a series of its own [INF]
            self.blocked = True

    def _spline_close(self) -> None:
        """End the open spline series (if any): the waiting point's move, with the added
        zero-distance segment to rest (TUM p290), is calculated."""
        series = self.spline
        if series is not None:
            self.spline = None
            if self._ver != self.vars.version:
                self._refresh()
            self.planned.append(series.close(self._scale))

    # -- the planning context of the move modes (modes.move.PlanContext) --------------------

    @property
    def feedrate(self) -> float:
        return self._f

    @property
    def isx90_ms(self) -> float:
        return self._isx90

    @property
    def accel_prog_s(self) -> float:
        return self._ta_prog

    @property
    def accel_real_s(self) -> float:
        return self._ta_s

    @property
    def special_lookahead(self) -> bool:
        return self._la_s > 0

    @property
    def scurve_prog_s(self) -> float:
        return self._ts_prog

    @property
    def time_scale(self) -> float:
        return self._scale

    @property
    def segmented(self) -> bool:
        return self._isx13 > 0


__all__ = ["Planning"]
