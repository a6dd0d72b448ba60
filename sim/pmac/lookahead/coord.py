"""One coordinate system running its program: on-line commands, status words.

The coordinate system joins three parts, each its own module, over one declared state
(:mod:`.state`): :mod:`.planning` (working through lines at RTIs, the lookahead depth and
breaks, I11), :mod:`.execution` (blending, stops, the calculation deadline, ``Q`` / ``A`` /
``S``, positions) and :mod:`.timebase` (``%`` and ``H``). Every move mode's timing and
profile is its own module in :mod:`motionsim.sim.pmac.modes`. Program states and their
transitions: :mod:`.states`.
"""

from __future__ import annotations

from typing import Any

from ...errors import NotSimulated
from ...simpy_adapter import cancel
from ..card.variables import isx
from ..modes import DWELL, PROFILES
from .execution import Execution
from .planning import Planning
from .states import IDLE, RUNNING, STOPPED, WAITING
from .timebase import TimeBase

#: ``??`` word 2 move-mode bits (4, 1, 0): LINEAR 000, RAPID 010, CIRCLE1 001, CIRCLE2 011,
#: SPLINE 101, PVT 110 (TSRM p286-287; PSRM p195).
_MODE_BITS = {
    "LINEAR": 0, "RAPID": 0b10, "CIRCLE1": 0b01, "CIRCLE2": 0b11,
    "SPLINE1": 0b10001, "SPLINE2": 0b10001, "PVT": 0b10010,
}  # fmt: skip


class CoordSystem(Planning, Execution, TimeBase):
    """Coordinate system ``cs`` of a :class:`motionsim.sim.pmac.controller.PmacController`.

    Its state is declared in :class:`.state.CoordState` (the base of every part); this class
    adds the on-line commands that touch more than one part, and the status words."""

    @property
    def moving(self) -> bool:
        return self.current is not None

    @property
    def run_time_error(self) -> bool:
        """Aborted because calculation fell behind (``??`` word 2 bit 22, motor ``?`` word 1
        bit 14)."""
        return self.error == "run_time_error"

    # -- on-line commands -----------------------------------------------------------------

    def run(self, single_step: bool = False) -> None:
        """``R`` / ``S``: start (or resume) calculation at the next RTI; after ``H``, resume."""
        if self._held:
            self._held = False
            self._slew_to(self.commanded_override, 95)  # R after H ramps back at Isx95
        self.single_step = single_step
        self.step_lines = 1 if single_step and self.vars.I(isx(self.cs, 53)) == 1 else None
        self.quitting = False
        self._end_stop = False
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

    def stop_at_end(self) -> None:
        """``/``: with Isx13 > 0 stop at the end of the move executing now, undoing a blend
        already decided into the next one (TUM p217, the table of stop commands: "end of
        currently executing move", TA / TS deceleration, on the path, at a programmed
        point); the moves already calculated stay and run on ``R`` / ``S``. With Isx13 = 0
        it acts as ``Q`` (TSRM p177). A stop ramp that no longer fits before the move's end
        is shortened to the time left ``[INF]``."""
        if not self._segmented() or self.current is None or not self.running:
            self.quit()
            return
        m = self.current
        self.quitting = True
        self._end_stop = True
        if m.stopping:
            return
        if self.planned:
            self.planned[0].ta_in = self.planned[0].ta  # a blend into it is undone
        self._decided = m
        m.stopping = True
        now = self._env._now
        if PROFILES[m.kind].stop_ramp:
            ta = self._accel_s()
            ta = max(ta, m.ta_stop * self._scale) if m.ta_stop else ta
            ta = min(ta, max(0.0, 2 * (m.b_end - now)))
        else:
            ta = 0.0
        m.ta_out = ta
        self._after(self.sched.servo_at_or_after(m.b_end + ta / 2), self._stop_end)

    def quick_stop(self) -> None:
        """``\\``: outside the special lookahead (and always with Isx13 = 0) it acts as ``H``
        (TUM p217; TSRM p177). The quick stop inside an active special lookahead (Isx13 > 0,
        Isx20 > 0, ``DEFINE LOOKAHEAD``: stop along the path within the Ixx17 limits, resumed
        by ``>`` / ``R``, TSRM p181 Isx21 = 4) is not simulated: it raises
        :class:`~motionsim.sim.errors.NotSimulated` and changes nothing."""
        if self._ver != self.vars.version:
            self._refresh()
        if self._la_s > 0 and self.current is not None:
            raise NotSimulated(
                "\\ (quick stop in the special lookahead, Isx20 > 0 with DEFINE LOOKAHEAD) is "
                "valid Turbo PMAC but not simulated; outside the lookahead it acts as H",
                pmac_error="ERR003")
        self.hold()

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
        cancel(self._slew_wake)
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
