"""The synchronous M-variable queue of a coordinate system, served at RTIs.

What the Turbo User Manual says (TUM p249-250, p319; spec §4.4, §11.4):

* ``M{n}=={expr}``, ``&=``, ``|=``, ``^=``: the right side is evaluated when the line is
  calculated; variable, operator and value go on a queue. They are performed "where the
  blending to the new move begins" — the start of the next move (or DWELL) that actually
  executes. In LINEAR / CIRCLE without segmentation that is V·TA/2 ahead of the programmed
  point: here the instant the move's blend ramp begins, which is its ``move_start``.
* With segmentation (Isx13 > 0) they run "at the start of the first Isx13 spline segment
  after the start of blending into the programmed move".
* The card "checks to see whether it is time to pull synchronous assignments out of the
  queue ... every real-time interrupt (every I8+1 servo cycles)": so a write lands on the
  **first RTI at or after** the instant above, not on the servo cycle the move starts.
* ``&=`` / ``|=`` / ``^=`` read the variable when the write is performed (the read-modify-write
  happens then, PUM p160); ``==`` just writes the value calculated earlier.
* Assignments after the last move / DWELL are not performed when the program ends or stops;
  they stay queued until the next move executes, or until on-line ``MFLUSH`` removes them.
  ``A`` and CTRL-K discard queued writes (TUM p319).

Inferences ``[INF]``:

* "Start of the move" is the servo cycle of ``move_start``: the start of the blend ramp for a
  blended LINEAR / CIRCLE / DELAY / PVT move, the move's first cycle when it starts from rest
  (the first move, the move after a DWELL / RAPID / PSET break or a run-out), the DWELL's or
  RAPID's first cycle.
* Segments: with Isx13 > 0 the coarse-interpolation segments of a LINEAR (CIRCLE) or DELAY
  sequence start when the sequence starts from rest and follow every Isx13 ms of real time
  (the ``%`` time base does not re-grid them); other move kinds (DWELL, RAPID, PVT) are not
  segmented, so their writes wait for the RTI only.
* In the RTI the queue is served before move planning (a write and a planning pass due at the
  same RTI: the write first), so an expression calculated at that RTI already sees it.
* ``MFLUSH`` empties the whole queue: writes waiting for their RTI, writes calculated with
  moves that have not started, and the leftovers after the last move.
"""

from __future__ import annotations

import math
from collections import deque
from typing import TYPE_CHECKING, Any

from ...simpy_adapter import cancel
from ..language.expressions import pmac_and, pmac_or, pmac_xor
from ..tasks.scheduler import Scheduler, Wake, wake_at

if TYPE_CHECKING:
    import simpy

    from ..card.variables import Variables

#: One queued write: ``(M-variable number, operator, value)``.
Write = tuple[int, str, float]

#: Synchronous read-modify-write forms.
_BITWISE = {"&=": pmac_and, "|=": pmac_or, "^=": pmac_xor}


def segment_start(t: float, t0: float, seg_s: float) -> float:
    """The first segment boundary at or after ``t`` of segments of ``seg_s`` starting at
    ``t0`` (Isx13 > 0: "the first Isx13 spline segment after the start of blending")."""
    if seg_s <= 0 or t <= t0:
        return t
    k = math.ceil((t - t0) / seg_s - 1e-9)
    return t0 + k * seg_s


class SyncQueue:
    """Writes whose move has started, waiting for their RTI (oldest first).

    Args:
        env: the controller's environment.
        sched: its servo / RTI instants.
        vars_: the card's variables, where the writes go (``mvar`` events, ``sync=True``).
        cs: the coordinate system (the context of its M-variables).
    """

    def __init__(
        self, env: simpy.Environment, sched: Scheduler, vars_: Variables, cs: int
    ) -> None:
        self._env = env
        self._sched = sched
        self._vars = vars_
        self._cs = cs
        self._due: deque[tuple[float, list[Write]]] = deque()
        self._wake: Wake | None = None

    def started(self, writes: list[Write], t_ready: float) -> None:
        """The move carrying ``writes`` has reached the instant they may be performed
        (``t_ready``): they are performed at the first RTI at or after it — now, when now
        is that RTI and nothing older is waiting."""
        t = self._sched.rti_at_or_after(t_ready)
        now = self._env._now
        if not self._due and t <= now:
            for k, aop, value in writes:
                self._write(k, aop, value)
            return
        self._due.append((t, writes))
        if len(self._due) == 1:
            self._wake = wake_at(self._env, t if t > now else now, self._serve, self._wake)

    def _write(self, k: int, aop: str, value: float) -> None:
        """Perform one write: ``==`` writes the value calculated earlier; ``&=`` / ``|=`` /
        ``^=`` read the variable now (PUM p160)."""
        vars_ = self._vars
        if aop == "==":
            vars_.write("M", k, value, self._cs, sync=True)
            return
        old = vars_.read("M", k, self._cs)
        vars_.write("M", k, _BITWISE[aop](old, value), self._cs, sync=True)

    def _serve(self, _ev: Any) -> None:
        """An RTI with writes due: perform them in queue order, re-arm for the next."""
        due = self._due
        now = self._env._now
        while due and due[0][0] <= now:
            for k, aop, value in due.popleft()[1]:
                self._write(k, aop, value)
        if due:
            self._wake = wake_at(self._env, due[0][0], self._serve, self._wake)

    def discard(self) -> None:
        """Drop every waiting write (``A``, CTRL-K, ``MFLUSH``, reset)."""
        self._due.clear()
        cancel(self._wake)


__all__ = ["SyncQueue", "Write", "segment_start"]
