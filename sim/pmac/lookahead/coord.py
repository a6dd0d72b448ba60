"""One coordinate system running its program: state, on-line commands, status words.

The coordinate system joins three parts, each its own module: :mod:`.planning` (working
through lines at RTIs, the lookahead depth and breaks, I11), :mod:`.execution` (blending,
stops, the calculation deadline, ``Q`` / ``A`` / ``S``, positions) and :mod:`.timebase`
(``%`` and ``H``). Every move mode's timing and profile is its own module in
:mod:`motionsim.sim.pmac.modes`. Program states and their transitions: :mod:`.states`.
"""

from __future__ import annotations

from collections import deque
from typing import TYPE_CHECKING, Any

from motionsim.sim.pmac.buffers import motion
from motionsim.sim.pmac.card.variables import isx
from motionsim.sim.pmac.lookahead.execution import Execution
from motionsim.sim.pmac.lookahead.planning import Planning
from motionsim.sim.pmac.lookahead.states import IDLE, RUNNING, STOPPED, TRANSITIONS, WAITING
from motionsim.sim.pmac.lookahead.sync_queue import SyncQueue
from motionsim.sim.pmac.lookahead.timebase import TimeBase
from motionsim.sim.pmac.modes import DWELL, Move, RunTimeError, pvt, spline
from motionsim.sim.pmac.tasks.scheduler import Wake

if TYPE_CHECKING:
    from motionsim.sim.pmac.buffers.lookahead_buffer import LookaheadBuffer
    from motionsim.sim.pmac.buffers.programs import ProgramRun
    from motionsim.sim.pmac.buffers.rotary import RotaryBuffer
    from motionsim.sim.pmac.controller import PmacController
    from motionsim.sim.pmac.lookahead.abort_stop import AbortStop


#: ``??`` word 2 move-mode bits (4, 1, 0): LINEAR 000, RAPID 010, CIRCLE1 001, CIRCLE2 011,
#: SPLINE 101, PVT 110 (TSRM p286-287; PSRM p195).
_MODE_BITS = {
    "LINEAR": 0, "RAPID": 0b10, "CIRCLE1": 0b01, "CIRCLE2": 0b11,
    "SPLINE1": 0b10001, "SPLINE2": 0b10001, "PVT": 0b10010,
}  # fmt: skip


class CoordSystem(Planning, Execution, TimeBase):
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
        #: ``DEFINE LOOKAHEAD`` (:mod:`motionsim.sim.pmac.buffers.lookahead_buffer`); gone at reset.
        self._lookahead: LookaheadBuffer | None = None
        #: The special lookahead's horizon, min(Isx20, segments) × Isx13 (s); 0 = not active.
        self._la_s = 0.0
        self.program: float | None = None  # B{n}; 0 = rotary
        #: The fixed program being run (B{n}, n > 0), :mod:`motionsim.sim.pmac.buffers.programs`.
        self.fixed: ProgramRun | None = None
        self.state = IDLE
        self.planned: deque[Move] = deque()
        self.current: Move | None = None
        #: Synchronous writes calculated after the last calculated move: they go with the
        #: next move calculated (:mod:`.sync_queue`).
        self.sync_pending: list[tuple[int, str, float]] = []
        #: Writes whose move has started, waiting for their RTI (TUM p250).
        self.sync_queue = SyncQueue(ctl.env, ctl.scheduler, self._sync_write)
        self._seg_t0 = 0.0  # Isx13 > 0: where the segments of the present sequence start
        self.blocked = False
        self.quitting = False
        self.single_step = False
        #: With Isx53 = 1 a step (``S``) executes one program line: the lines it may still
        #: take (TSRM p182); None otherwise.
        self.step_lines: int | None = None
        self._plan_due: float | None = None
        self._plan_wake: Wake | None = None  # the last planning wake-up (re-used, wake_at)
        #: The pending execution wake-up (handoff, decision, stop); cancelled by emptying its
        #: callbacks (SimPy then processes it as a no-op).
        self._pending: Wake | None = None
        self._plan_cb_bound = self._plan_cb
        self._handoff_cb = self._start_next  # the blend into the next move starts
        self._stop_end_cb = self._stop_end
        self._decide_cb = self._decide
        self._abort: AbortStop | None = None  # the A deceleration under way
        self._isx13 = 0.0
        # Modal program state.
        self.mode = "LINEAR"  # (sets the lookahead depth, Planning._depths)
        self.time_mode = False
        self.incremental: set[str] = set()
        self.frax: tuple[str, ...] = ("X", "Y", "Z")  # FRAX (axis_definitions)
        self._fast = 0  # the planning short cut for constant lines (Planning._fast_kind)
        self._pvt_t = 0.0  # the PVT segment time (program s), 0 if out of range
        self._pvt_to_s = 1.0  # PVT velocity (units per Isx90 ms) to tangent (units/segment)
        self.no_blend = False  # Isx92 = 1 at the last R / S: stop and re-plan after each move
        #: ``%`` feedrate override (the CS time base), see :meth:`set_feed_override`.
        self.feed_override = 100.0
        self.calc_pos: dict[str, float] = {}
        #: End velocities of the last calculated PVT segment (user units per Isx90 ms), the
        #: next segment's start; empty after any other move.
        self.calc_vel: dict[str, float] = {}
        self.rest_pos: dict[str, float] = {}
        #: The open SPLINE1 / SPLINE2 series: its last point waits for the next one.
        self.spline: spline.Series | None = None
        self._ver = -1
        self._ta_s = 0.0
        self._ta_prog = 0.0
        self._ts_prog = 0.0  # TS (Isx88) in whole ms, program seconds
        #: Axis velocities (units/s, program time) of the last calculated LINEAR move, for
        #: Ixx17 at the next corner (:mod:`motionsim.sim.pmac.modes.accel_limit`); None after
        #: any other move.
        self._lin_w: dict[str, float] | None = None
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

    # -- on-line commands -----------------------------------------------------------------

    def run(self, single_step: bool = False) -> None:
        """``R`` / ``S``: start (or resume) calculation at the next RTI; after ``H``, resume."""
        if self._held:
            self._held = False
            self._slew_to(self.commanded_override, 95)  # R after H ramps back at Isx95
        self.single_step = single_step
        self.step_lines = 1 if single_step and self.vars.I(isx(self.cs, 53)) == 1 else None
        self.quitting = False
        self.error = None
        # Isx92 (move blend disable) is read only at R / S (TSRM p190).
        self.no_blend = self.vars.I(isx(self.cs, 92)) == 1
        self._fast = 0  # re-derived at the next calculated line
        if self.state != RUNNING and self.state != WAITING:
            self._set_state(RUNNING)
        self._request_plan()
        if self.current is None and not self._starting:
            self._arm_i11()

    def quit(self) -> None:
        """``Q``: finish the calculated moves, calculate nothing more, then ``stopped``."""
        if not self.running:
            return
        # Synchronous writes left after the last calculated move stay queued (TUM p250:
        # removed only by MFLUSH).
        if self.current is None and not self.planned:
            self._plan_due = None
            self._set_state(STOPPED)
            return
        self.quitting = True  # (an I11-delayed start still runs the calculated moves)

    def mflush(self) -> None:
        """``MFLUSH``: empty the synchronous M-variable queue (TUM p250) — the writes left
        after the last move, those calculated with moves not yet started, and those waiting
        for their RTI ``[INF]``. Nothing else changes; a running program goes on."""
        self.sync_pending.clear()
        for m in self.planned:
            m.sync = None
        if self.spline is not None:
            self.spline.sync = []  # the waiting spline point's writes
        self.sync_queue.discard()

    def detach(self) -> None:
        """Forget every scheduled wake-up (the controller is being reset)."""
        self._plan_due = None
        self._cancel()
        self.spline = None
        self.sync_queue.discard()
        wake = self._slew_wake
        if wake is not None and wake.callbacks:
            wake.callbacks.clear()
        self._slew_wake = None
        self.state = IDLE

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
        w2 |= _MODE_BITS[self.mode]
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


__all__ = ["CoordSystem"]
