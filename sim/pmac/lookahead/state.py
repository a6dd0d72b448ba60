"""The state of one coordinate system, declared in one place.

:class:`CoordState` is the base of :class:`~motionsim.sim.pmac.lookahead.CoordSystem` and of
its three parts (:mod:`.planning`, :mod:`.execution`, :mod:`.timebase`): every attribute any
part reads or writes is set in :meth:`CoordState.__init__`, annotated and grouped by the
concern that owns it, so a part's ``self.x`` is found here by name. Besides the state it holds
the few rules every part needs: the program-state transition (:mod:`.states`), where lines are
read from, and the cache of the CS I-variables (re-read whenever the variable store's version
moves on).

The state stays flat on the object (no sub-objects per concern): the per-line path of a
rotary stream reads a dozen of these attributes per line, and one more attribute lookup each
is measurable there (``bench/bench_pmac_stream.py``).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from ..buffers import motion
from ..card.variables import isx
from ..modes import Move, RunTimeError, pvt, spline
from .states import IDLE, RUNNING, STOPPED, TRANSITIONS, WAITING
from .sync_queue import SyncQueue, Write

if TYPE_CHECKING:
    import simpy

    from ...events import EventLog
    from ...simpy_adapter import Wake
    from ..buffers.lookahead_buffer import LookaheadBuffer
    from ..buffers.programs import ProgramRun
    from ..buffers.rotary import RotaryBuffer
    from ..card.variables import Variables
    from ..controller import PmacController
    from ..tasks.scheduler import Scheduler
    from .abort_stop import AbortStop

#: Modes calculated two moves ahead without segmentation (TUM p339: LINEAR, and CIRCLE, which
#: then runs as LINEAR, TSRM p177); SPLINE needs two ahead always; PVT and RAPID one.
_TWO_AHEAD = frozenset({"LINEAR", "CIRCLE1", "CIRCLE2"})
SPLINES = frozenset({"SPLINE1", "SPLINE2"})


class CoordState:
    """Everything a coordinate system knows, by concern (see the module docstring)."""

    if TYPE_CHECKING:  # the wake-up callbacks of the parts (:mod:`.planning`, :mod:`.execution`)

        def _plan_cb(self, _ev: object) -> None: ...
        def _start_next(self, _ev: object = None) -> None: ...
        def _decide(self, _ev: object) -> None: ...

    def __init__(self, ctl: PmacController, cs: int) -> None:
        # -- wiring: the card this CS belongs to ----------------------------------------------
        self.ctl = ctl
        self.cs = cs
        self.vars: Variables = ctl.vars
        self.sched: Scheduler = ctl.scheduler
        self._env: simpy.Environment = ctl.env
        self._period: float = ctl.scheduler.period_s
        log: EventLog = ctl.log
        self._emit: Callable[..., object] = log.emit
        self._row = log.emit_row  # the per-line move_start / move_end (the hot path)

        # -- the program: where lines come from, its state (:mod:`.states`) --------------------
        self.rotary: RotaryBuffer | None = None
        #: ``DEFINE LOOKAHEAD`` (:mod:`motionsim.sim.pmac.buffers.lookahead_buffer`); gone at
        #: reset. Set through the ``lookahead`` property (the horizon is re-derived).
        self._lookahead: LookaheadBuffer | None = None
        self.program: float | None = None  # B{n}; 0 = rotary
        #: The fixed program being run (B{n}, n > 0), :mod:`motionsim.sim.pmac.buffers.programs`.
        self.fixed: ProgramRun | None = None
        self.state: str = IDLE
        #: Why the controller aborted the program by itself, until the next ``R`` / ``S`` or
        #: reset: ``"run_time_error"`` (calculation fell behind) or ``"watchdog"``.
        self.error: str | None = None

        # -- calculation (:mod:`.planning`): what is calculated, and when next ---------------
        #: Calculated moves not yet executing, oldest first.
        self.planned: deque[Move] = deque()
        #: Synchronous writes calculated after the last calculated move: they go with the
        #: next move calculated (:mod:`.sync_queue`).
        self.sync_pending: list[Write] = []
        #: A lookahead break (DWELL, RAPID, PSET, WAIT, Isx92 = 1) stops calculation until
        #: the move before it has ended.
        self.blocked = False
        self.quitting = False  # ``Q`` given: calculate nothing more
        self.single_step = False  # ``S``: one move (or one line, below), then stopped
        #: With Isx53 = 1 a step (``S``) executes one program line: the lines it may still
        #: take (TSRM p182); None otherwise.
        self.step_lines: int | None = None
        #: The "plan the next move" flag: the RTI at which the next planning pass
        #: (:meth:`.Planning._plan_cb`) is due, None when none is asked for.
        self._plan_due: float | None = None
        self._plan_wake: Wake | None = None  # that pass's wake-up (re-used, wake_at)
        #: The rotary line count when planning last had its chance: a line loaded after it
        #: is a run-out, not a run-time error (:meth:`.Execution._fell_behind`).
        self._seen_n = 0
        #: The planning short cut the next constant line may take (:meth:`.Planning._fast_kind`;
        #: 0 = none, re-derived after every line taken the long way).
        self._fast = 0

        # -- modal program state (what the lines calculated next mean) -----------------------
        #: Calculation keeps this many moves ready: (a move executing, from rest); set with
        #: the mode and Isx13 (:meth:`_depths`).
        self._depth_at: tuple[int, int] = (2, 3)
        self._isx13 = 0.0  # (read by the mode setter below; the I-variable cache)
        self._mode = "LINEAR"
        self.mode = "LINEAR"  # LINEAR, RAPID, CIRCLE1/2, PVT, SPLINE1/2 (sets _depth_at)
        self.time_mode = False  # TM (True) or F (False) sets the move time
        self.incremental: set[str] = set()  # axes in INC mode
        self.abs_radius = False  # ABS(R): circle centre vectors from the origin (INC(R) default)
        self.frax: tuple[str, ...] = ("X", "Y", "Z")  # FRAX (axis_definitions)
        #: Axis positions at the end of the last calculated move (program units).
        self.calc_pos: dict[str, float] = {}
        #: End velocities of the last calculated PVT segment (user units per Isx90 ms), the
        #: next segment's start; empty after any other move.
        self.calc_vel: dict[str, float] = {}
        #: The open SPLINE1 / SPLINE2 series: its last point waits for the next one.
        self.spline: spline.Series | None = None
        #: Axis velocities (units/s, program time) of the last calculated LINEAR move, for
        #: Ixx17 at the next corner (:mod:`motionsim.sim.pmac.modes.accel_limit`); None after
        #: any other move.
        self._lin_w: dict[str, float] | None = None

        # -- starting a sequence from rest: the I11 delay (:meth:`.Planning._arm_i11`) -------
        self._starting = False  # an I11 delay before the first move is running
        #: The instant the first move of the sequence being started is due, and the wake-up
        #: that checks it was calculated by then.
        self._go_t: float | None = None
        self._i11_wake: Wake | None = None

        # -- execution (:mod:`.execution`): the move under way and what ends it --------------
        self.current: Move | None = None
        #: The pending execution wake-up: the hand-off into the next move
        #: (:meth:`.Execution._start_next`), a segmented-mode decision (``_decide``), a stop's
        #: end (``_stop_end``) or an ``A`` stop's end (``_abort_end``); one at a time.
        self._pending: Wake | None = None
        self._decided: Move | None = None  # segmented mode: the move whose blend is decided
        #: ``/`` with Isx13 > 0: the executing move ends in a stop and the moves calculated
        #: after it wait for the next ``R`` / ``S`` (:meth:`.CoordSystem.stop_at_end`).
        self._end_stop = False
        #: The motors whose home search a program ``HOME`` waits for (:mod:`..modes.home`).
        self._homing: list[int] = []
        self._abort: AbortStop | None = None  # the A deceleration under way
        #: Commanded axis positions while no move executes.
        self.rest_pos: dict[str, float] = {}
        self._seg_t0 = 0.0  # Isx13 > 0: where the segments of the present sequence start
        self.no_blend = False  # Isx92 = 1 at the last R / S: stop and re-plan after each move
        #: Writes whose move has started, waiting for their RTI (TUM p250).
        self.sync_queue = SyncQueue(ctl.env, ctl.scheduler, ctl.vars, cs)
        #: Called ``(move, t)`` as each move starts, in a kinematic CS (sim.pmac.kinematics).
        self.on_move_start: Callable[[Move, float], None] | None = None
        #: The per-line wake-ups' callbacks, bound once (a bound method made per wake-up is
        #: measurable on the streaming path): the planning pass and the hand-off.
        self._plan_fn: Callable[[object], None] = self._plan_cb
        self._start_fn: Callable[[object], None] = self._start_next
        self._decide_fn: Callable[[object], None] = self._decide  # (a PVT segment's hand-off)

        # -- the time base (:mod:`.timebase`): ``%`` and ``H`` --------------------------------
        #: The actual ``%`` (the CS time base, what ``%`` reports), see ``set_feed_override``.
        self.feed_override = 100.0
        #: The commanded ``%`` (the slew's goal; ``R`` after ``H`` returns to it).
        self.commanded_override = 100.0
        self._pct_before_hold = 100.0  # the time base of the profile frozen by %0 / H
        self._frozen_at = 0.0  # when the time base reached 0
        self._held = False  # ``H`` given (``R`` ramps back at Isx95)
        self._slew_target = 100.0
        self._slew_ivar = 94  # the slew-rate I-variable in use (Isx94, or Isx95 for H / R)
        self._slew_wake: Wake | None = None  # the next servo cycle of a slew

        # -- the I-variable cache (:meth:`_refresh`, whenever ``vars.version`` moved on) -----
        self._ver = -1  # the variable store's version these were read at
        #: The special lookahead's horizon, min(Isx20, segments) × Isx13 (s); 0 = not active.
        self._la_s = 0.0
        self._scale = 1.0  # time-base stretch: real seconds per program second (100 / %)
        self._ta_prog = 0.0  # max(TA, 2·TS) (Isx87, Isx88), program seconds
        self._ts_prog = 0.0  # TS (Isx88) in whole ms, program seconds
        self._ta_s = 0.0  # the same in real seconds
        self._f = 1000.0  # Isx89: F, or the TM time (ms)
        self._isx90 = 1000.0  # Isx90: the feedrate time unit (ms)
        self._rti = 3  # I8 + 1: servo cycles per RTI
        self._tm_s = 1.0  # the TM-mode move time, real seconds
        self._i11_s = 0.0  # I11: the calculation delay of a start from rest (s)
        self._pvt_t = 0.0  # the PVT segment time (program s), 0 if out of range
        self._pvt_to_s = 1.0  # PVT velocity (units per Isx90 ms) to tangent (units/segment)

    # -- program state -------------------------------------------------------------------

    def _set_state(self, state: str, **extra: Any) -> None:
        if state == self.state:
            return
        if state not in TRANSITIONS[self.state]:
            raise AssertionError(f"program state {self.state} -> {state} is not legal")
        self.state = state
        self._emit("program", cs=self.cs, state=state, **extra)

    def lines(self) -> RotaryBuffer | ProgramRun | None:
        """Where planning reads program lines: the rotary buffer (``B0``) or the fixed
        program the CS was pointed at (``B{n}``); both offer the same interface."""
        return self.rotary if self.program == 0 else self.fixed

    def _ran_out(self) -> None:
        """Running, motion at rest and nothing left to calculate: a fixed program has come to
        its end (``stopped``, TSRM p381); a rotary program waits for more lines."""
        src = self.lines()
        ended = src is not None and getattr(src, "ends", False) and not src.pending
        self._set_state(STOPPED if ended else WAITING)

    @property
    def running(self) -> bool:
        """Running in the controller's sense: ``R`` given, not stopped (waiting included)."""
        return self.state == RUNNING or self.state == WAITING

    # -- the modal move mode and the lookahead depth it sets -----------------------------

    @property
    def mode(self) -> str:
        """The move mode (LINEAR, CIRCLE1, PVT, SPLINE1, ...) of the lines calculated next."""
        return self._mode

    @mode.setter
    def mode(self, mode: str) -> None:
        self._mode = mode
        self._depth_at = self._depths()

    def _depths(self) -> tuple[int, int]:
        """How many moves calculation keeps ready (TUM p339, spec §4.2): 2 beyond the
        executing one with Isx13 = 0 for LINEAR, and CIRCLE, which then runs as LINEAR
        (TSRM p177), and SPLINE; else 1; one more from rest, where no move executes yet.
        Returns (with a move executing, from rest), kept as ``_depth_at`` — indexed by
        ``current is None`` — and re-derived whenever the mode or Isx13 changes."""
        mode = self._mode
        depth = 2 if (self._isx13 == 0 and mode in _TWO_AHEAD) or mode in SPLINES else 1
        return depth, depth + 1

    # -- the I-variable cache ------------------------------------------------------------

    def _refresh(self) -> None:
        """Re-read the CS I-variables (Isx13, Isx87, Isx88) after any I-variable change."""
        v, cs = self.vars, self.cs
        self._ver = v.version
        self._fast = 0  # the short cut is re-derived from these settings at the next line
        self._isx13 = v.I(isx(cs, 13))
        self._depth_at = self._depths()
        la, isx20 = self._lookahead, int(v.I(isx(cs, 20)))
        segs = min(isx20, la.segments) if la is not None else 0
        self._la_s = segs * self._isx13 / 1000.0 if self._isx13 > 0 and segs > 0 else 0.0
        pct = self.feed_override if self.feed_override > 0 else self._pct_before_hold
        self._scale = 100.0 / pct  # time-base stretch: real seconds per program second
        self._ta_prog = motion.accel_time_s(v.I(isx(cs, 87)), v.I(isx(cs, 88)))
        self._ts_prog = motion.whole_ms(v.I(isx(cs, 88))) / 1000.0
        self._ta_s = self._ta_prog * self._scale
        self._f = v.I(isx(cs, 89))
        self._isx90 = v.I(isx(cs, 90))
        self._rti = int(v.I(8)) + 1
        # TM-mode move time, real seconds
        self._tm_s = motion.clamp_move_time(self._f / 1000.0, self._ta_prog) * self._scale
        self._i11_s = max(0.0, v.I(11)) / 1000.0
        try:
            self._pvt_t = pvt.segment_ms(self._f) / 1000.0
        except RunTimeError:
            self._pvt_t = 0.0
        self._pvt_to_s = self._pvt_t * 1000.0 / self._isx90 if self._isx90 else 0.0

    @property
    def lookahead(self) -> LookaheadBuffer | None:
        """The special lookahead buffer (``DEFINE LOOKAHEAD``), or None."""
        return self._lookahead

    @lookahead.setter
    def lookahead(self, buf: LookaheadBuffer | None) -> None:
        self._lookahead = buf
        self._ver = -1  # the lookahead horizon is re-derived with the I-variables

    def _accel_s(self) -> float:
        if self._ver != self.vars.version:
            self._refresh()
        return self._ta_s

    def _segmented(self) -> bool:
        if self._ver != self.vars.version:
            self._refresh()
        return self._isx13 > 0

    # -- the motors of this CS's axes ----------------------------------------------------

    def motors_of(self, axis: str) -> list[tuple[int, float]]:
        """``(motor, counts per axis unit)`` of every motor assigned to ``axis`` here."""
        ctl = self.ctl
        out = []
        for n in ctl.motors:
            have = ctl._motor_axis(n)
            if have is not None and have[0] == self.cs and have[1] == axis:
                out.append((n, have[2]))
        return out


__all__ = ["SPLINES", "CoordState"]
