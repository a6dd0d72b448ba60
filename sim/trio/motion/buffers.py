"""THE placement rule of the Trio Motion Coordinator: MTYPE -> NTYPE -> process buffer.

Every axis has two move buffers — MTYPE (the move executing) and NTYPE (the next move) — and
every process has one process buffer, shared by all the axes it drives (TN20-16, spec §1).
This module alone decides where a move goes and when it moves on.

Placement, at the instant a move command is issued by process ``p`` on axes ``A`` (TRM
MC206 p. 8-130 "PMOVE", M206-320): the move is first written into ``p``'s process move buffer
(PMOVE = 1) and the program goes on with its next line; the *next servo interrupt* transfers it
to the NTYPE buffers of every axis in ``A`` if they are all free (PMOVE = 0), and — in the same
interrupt, sequencing first — on into MTYPE where MTYPE is free. So:

1. ``p``'s process buffer is full -> the move cannot be buffered: a BASIC process waits at
   the line, the command line locks, the REST API answers 409 ``buffer_full``. Two moves
   issued by one process within one servo period therefore make the second one wait for the
   interrupt (TN20: a fourth move blocks; here the second already does until the transfer);
2. else -> ``p``'s process buffer (PMOVE = 1), a servo interrupt is scheduled at the next
   period; with every buffer of ``A`` empty the move starts executing at that period.

MC4xx: NTYPE is the head of a per-axis look-ahead of ``depth`` (LIMIT_BUFFERED) moves
(TJ2H-57); sequencing needs room in the look-ahead of every axis of the move, loading needs the
move to be first in line on all of them. On the MC2xx generation the depth is 1 (NTYPE only).

Then, at every servo period ``k`` at which something can change, in this order (TJ2P-21):

1. *sequencing*: a process buffer move goes to NTYPE when the NTYPE of **every** axis it
   needs is free (all or nothing; PMOVE back to 0);
2. *move loading*: an NTYPE move goes to MTYPE when the MTYPE of every axis it needs is free,
   and starts at ``k``;
3. the MTYPE moves advance; a move whose profile ends at ``k`` ends there (MTYPE = 0).

So "the instant the move in the MTYPE register is finished, the buffered move is pulled
forward and starts in the next servo period" (TN20): a move ending at cycle ``e`` is followed
by its NTYPE move starting at ``e + 1``, and the process buffer drains into the freed NTYPE at
``e + 2`` (sequencing precedes loading, spec §1.2 ``[INF]``). A process waiting at a move line
has its move written to the process buffer in the servo period where the buffer drained, and
that move is transferred at the following interrupt.

MERGE (axis parameter of the base axis, default OFF). Not found in any corpus reachable here
(searched docs/pages/code/issues for "Trio MERGE axis parameter", "Trajexia MERGE parameter
motion buffer next move loaded", "MERGE=ON Trio BASIC"; spec §1.6, §9.11 ``[BK]``). Modelled
from the Trio TRM entry as remembered, ``[BK]``: with MERGE ON and the next move already loaded in
NTYPE, the axes do not ramp down to zero at the end of the MTYPE move but run straight into
the next one; merging applies only to velocity-profiled moves (MOVE, MOVEABS, MOVECIRC,
MHELICAL) on the same axis group, and only the base axis' MERGE counts; the programmer must
make sure the merge is sensible (no check of direction reversal); with short moves a high
DECEL is needed because the decision is made before the ramp down starts. Here: when a
mergeable move enters NTYPE while MTYPE still holds a move that has not yet passed the point
where its profile starts to slow down for the end (``diverges_at``), the MTYPE move is
re-planned to end at speed (the part already run is unchanged). A move that enters NTYPE
later finds the ramp down under way and the pair is not merged. At a merged joint the NTYPE
move takes over MTYPE in the servo period ``e`` where the first ends (``move_end`` and
``move_start`` both at ``e``), its profile starting at the exact instant the previous one
ended, at its end speed: DPOS runs on without a pause and MTYPE, VP_SPEED and MSPEED never
read a stop (issue 22). Consecutive CAMBOX / MOVELINK on one link axis are joined the same way
(MOVELINK-MD: "merged together automatically"). CANCEL(1) of a move already merged onto leaves the
MTYPE move ending at speed (``[INF]``).

Software limits and the following-error trip stop a move before its end
(:mod:`motionsim.sim.trio.motion.guards`, the ``AxisGuards`` part of ``MotionBuffers``): they
are looked at in step 3 of a servo period, before the moves advance.

Only the servo periods where something happens cost a SimPy event: move ends are scheduled
when moves start, and a period is scheduled only when a buffer can move on.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable
from typing import Any

import simpy

from ...events import EventLog
from ...simpy_adapter import Wake, nothing_due_by, urgent_at
from ...timing import ServoClock
from ..card.basic_errors import BasicError
from ..card.scaling import nearest_edge
from .axis import Axis
from .datum import DatumMove
from .guards import AxisGuards
from .linked import LinkedMove
from .moves import Move
from .profile import diverges_at

Placed = str  # "mtype" | "ntype" | "process_buffer"

#: Velocity-profiled moves that MERGE can join end to end.
MERGEABLE = frozenset({"MOVE", "MOVEABS", "MOVECIRC", "MHELICAL"})
OnPlaced = Callable[[Placed], None]

#: The fields of the per-move events, in order (stored by
#: :meth:`motionsim.sim.events.EventLog.emit_row`: the dict is made when the event is read).
AXIS_KEYS = ("axis", "mtype", "ntype")
PROCESS_BUFFER_KEYS = ("process", "axis", "mtype")
MOVE_KEYS = ("axis", "mtype")  # move_start, move_end


def schedule_at(env: simpy.Environment, t: float, callback: Callable[[Any], None]) -> None:
    """Run ``callback`` at the absolute simulated instant ``t``, before normal events at ``t``.

    The servo interrupt pre-empts BASIC, so it runs with SimPy's URGENT priority. SimPy only
    offers relative delays, and ``now + (t - now)`` can miss ``t`` by a rounding step; the
    event is therefore pushed at ``t`` itself so every servo instant is exactly ``k * period``.
    """
    urgent_at(env, t, callback)


class Waiter:
    """A move waiting for its process buffer to free; ``cancel()`` withdraws it."""

    __slots__ = ("move", "on_placed", "alive", "resume")

    def __init__(self, move: Move, on_placed: OnPlaced, resume: bool = False) -> None:
        self.move = move
        self.on_placed = on_placed
        self.alive = True
        self.resume = resume  # on_placed resumes a program: called with None (_resume_placed)

    def cancel(self) -> None:
        self.alive = False


class MotionBuffers(AxisGuards):
    """Move buffers of all axes and process buffers of all processes of one controller."""

    #: A program resumed by the placement of its blocked move (:meth:`_resume_placed`) goes on
    #: inside the servo interrupt's own SimPy event when nothing else can come
    #: between (False: always through a wake-up of its own; the differential test runs both).
    resume_in_interrupt = True

    def __init__(
        self,
        env: simpy.Environment,
        clock: ServoClock,
        log: EventLog,
        axes: list[Axis],
    ) -> None:
        self.env = env
        self.clock = clock
        self.log = log
        self._row = log.emit_row  # the per-move events (the hot path)
        self.axes = axes
        self.process_buffer: dict[int, Move] = {}
        self._waiters: dict[int, deque[Waiter]] = {}
        self._ntype: list[Move] = []  # moves in NTYPE, oldest first
        self._active: dict[Move, None] = {}  # moves in MTYPE, oldest first
        self._ending: dict[int, list[Move]] = {}  # executing moves by the cycle they end
        self._ticks: set[int] = set()
        self._merged_from: dict[Move, tuple[float, float]] = {}  # next move: (t0, v0)
        self._watchers: list[tuple[Callable[[], bool], Callable[[], None]]] = []
        self._resumes: list[Callable[[Any], None]] = []  # see _resume_placed
        self._dead = False
        self._next_id = 0
        #: moves looked at every servo period: CAMBOX / MOVELINK ending by link distance, a
        #: CONNECT ramping at CLUTCH_RATE, a DATUM sequence watching its input
        self._links: dict[Any, None] = {}
        self._offsets: set[int] = set()  # axes with a DEFPOS / OFFPOS to apply
        self._init_guards()  # software limits, following error (guards.py)
        #: LIMIT_BUFFERED: moves the look-ahead of an axis holds, NTYPE included (TJ2H-57);
        #: 1 on the MC2xx generation (NTYPE only)
        self.depth = 1
        for ax in axes:
            ax.on_profile_change = self._profile_changed
        self._on_servo = self._servo  # bound once: the servo interrupt's callback

    def new_id(self) -> int:
        self._next_id += 1
        return self._next_id

    def shutdown(self) -> None:
        """Power cycle: scheduled servo periods of this instance do nothing any more."""
        self._dead = True
        for q in self._waiters.values():
            for w in q:
                w.alive = False

    # -- observation -----------------------------------------------------------------------

    def _changed(self, ax: Axis) -> None:
        m, nm = ax.mtype, ax.ntype
        self._row("axis", AXIS_KEYS,
                  (ax.n, m.mtype if m is not None else 0, nm.mtype if nm is not None else 0))
        if self._watchers:
            self._check_watchers()

    def _check_watchers(self) -> None:
        ready = [w for w in self._watchers if w[0]()]
        if ready:
            self._watchers = [w for w in self._watchers if w not in ready]
            for _pred, cb in ready:
                cb()

    def when(
        self, predicate: Callable[[], bool], callback: Callable[[], None]
    ) -> Callable[[], None]:
        """Call ``callback`` as soon as ``predicate()`` holds after a buffer change (or now).

        Used by ``WAIT IDLE`` / ``WAIT LOADED``; returns a function that withdraws the wait.
        """
        if predicate():
            callback()
            return lambda: None
        entry = (predicate, callback)
        self._watchers.append(entry)

        def withdraw() -> None:
            if entry in self._watchers:
                self._watchers.remove(entry)

        return withdraw

    def queued_for(self, axis: int) -> bool:
        """Whether a process buffer holds a move for ``axis`` (not yet in its NTYPE)."""
        return self.axes[axis].queued > 0

    def _pb_put(self, p: int, m: Move) -> None:
        self.process_buffer[p] = m
        for a in m.axes:
            self.axes[a].queued += 1
        self._row("process_buffer", PROCESS_BUFFER_KEYS, (p, m.axes[0], m.mtype))

    def _pb_take(self, p: int, emit: bool = True) -> Move:
        m = self.process_buffer.pop(p)
        for a in m.axes:
            self.axes[a].queued -= 1
        if emit:
            self._row("process_buffer", PROCESS_BUFFER_KEYS, (p, m.axes[0], 0))
        return m

    def pmove(self, process: int) -> int:
        """PMOVE: 1 while ``process``' process buffer holds a move."""
        return 1 if process in self.process_buffer else 0

    def _resume_placed(self) -> None:
        """The end of a servo period: call the ``on_placed`` of the waiters placed in it that
        resume a program (``place_or_wait(..., resume=True)``), with None, where wake-ups
        queued at this instant would.

        The wake-ups are queued here, in the order of placement (what the period does after
        step 4 queues nothing at this instant, so the order of events is the same as with a
        wake-up queued at each placement). When there is one, nothing else is due at this
        instant and nobody follows the log event by event (:attr:`EventLog.observed`), that
        wake-up would be the next event processed: it is called at once instead — the same
        events in the same order, one SimPy event less per blocked move line. (A driver
        stepping the environment event by event sees the program go on in the interrupt's
        own step.)"""
        fns, self._resumes = self._resumes, []
        env = self.env
        now = env._now
        if (len(fns) == 1 and self.resume_in_interrupt and not self.log.observed
                and nothing_due_by(env, now)):
            fns[0](None)
            return
        for fn in fns:
            Wake(env, now, fn)

    # -- placement -------------------------------------------------------------------------

    def place(self, move: Move, next_tick: int | None = None) -> Placed | None:
        """Write ``move`` into its process buffer (PMOVE = 1), or None when that is full.

        The next servo interrupt transfers it to NTYPE / MTYPE (see the module docstring);
        ``next_tick``: that interrupt's period when the caller knows it (a servo period
        placing a waiting move: the following one).
        """
        p = move.process
        if p in self.process_buffer:
            return None
        self._pb_put(p, move)
        k = self.clock.after(self.env._now) if next_tick is None else next_tick
        if k not in self._ticks:  # (most often that period runs already: no call)
            self._tick_at(k)
        return "process_buffer"

    def place_or_wait(self, move: Move, on_placed: OnPlaced,
                      resume: bool = False) -> Placed | Waiter:
        """Place ``move`` now, or queue it behind its process buffer (FIFO per process).

        ``on_placed(level)`` is called in the servo period where the process buffer frees and
        the move is placed; the returned :class:`Waiter` can be cancelled before that. With
        ``resume`` it resumes a waiting program instead: called with None where a wake-up
        queued at the placement would be (:meth:`_resume_placed`).
        """
        q = self._waiters.get(move.process)
        if not q and move.process not in self.process_buffer:
            placed = self.place(move)
            if placed is not None:
                return placed
        w = Waiter(move, on_placed, resume)
        self._waiters.setdefault(move.process, deque()).append(w)
        return w

    # -- cancelling ------------------------------------------------------------------------

    def cancel(self, axis: int) -> None:
        """CANCEL: the executing move on ``axis`` (and its group) decelerates at DECEL and
        ends; a move in NTYPE then starts as after any move end (spec §1.6 ``[BK]``)."""
        m = self.axes[axis].mtype
        if m is None:
            return
        assert m.profile is not None
        now_k = max(self.clock.index(self.env.now), m.start_tick or 0)
        tau = self.clock.t(now_k) - m.t_start
        base = self.axes[m.axes[0]]
        m.cancel_at(tau, base.decel, base.sramp / 1000.0)
        if not isinstance(m, DatumMove):  # a DATUM sequence ramps down in its own ticks
            self._links.pop(m, None)  # type: ignore[call-overload]
        self._reschedule_end(m, now_k)

    def _reschedule_end(self, m: Move, now_k: int) -> None:
        """The move's profile changed at period ``now_k``: end it where the profile ends."""
        assert m.profile is not None
        if m.profile.duration == math.inf:
            if m.end_tick is not None:
                old = self._ending.get(m.end_tick)
                if old and m in old:
                    old.remove(m)
                m.end_tick = None
            return
        end = max(self.clock.at_or_after(m.t_start + m.profile.duration), now_k + 1)
        self._end_at(m, end)

    def _profile_changed(self, ax: Axis) -> None:
        """SPEED / ACCEL / DECEL of ``ax`` written: re-plan the move it is the base axis of,
        from the servo period of the write (spec §10.5)."""
        m = ax.mtype
        if m is None or m.start_tick is None or m.axes[0] != ax.n or not m.follows_speed():
            return
        k = max(self.clock.index(self.env.now), m.start_tick)
        t = self.clock.t(k)
        m.replan(t - m.t_start, k, t, [self.axes[a] for a in m.axes])
        self._reschedule_end(m, k)
        self._arm_limits(m, k)

    def offset(self, axis: int) -> None:
        """DEFPOS / OFFPOS written for ``axis``: applied at the next servo period."""
        self._offsets.add(axis)
        self._tick_at(self.clock.after(self.env.now))

    def _apply_offsets(self, k: int) -> None:
        t = self.clock.t(k)
        for n in sorted(self._offsets):
            ax = self.axes[n]
            off = ax.pending_shift(t)
            ax.pending.clear()
            ax.pos += off
            m = ax.mtype
            if m is not None and m.start_tick is not None:
                m.shift(m.axes.index(n), off)
                self._arm_limits(m, k)
            for lm in self._active:
                if isinstance(lm, LinkedMove) and lm.link is ax:
                    lm.link_shifted(off)
            self.log.emit("offpos", axis=n, offset=off)
        self._offsets.clear()

    def _reconnect(self, new: Move, k: int) -> bool:
        """CONNECT on an axis already CONNECTed to the same driving axis: the ratio changes
        from this servo period on, without a step (TJ2P-71); consumed (True). One naming
        another driving axis waits behind the first until that is CANCELled."""
        ax = self.axes[new.axes[0]]
        old = ax.mtype
        if (
            not isinstance(old, LinkedMove) or old.kind != "CONNECT" or ax.ntype is not None
            or not isinstance(new, LinkedMove) or old.link is not new.link or old.cancelled
        ):
            return False
        old.rebase_ratio(self.clock.t(k), new.args[0], ax)
        if old.needs_tick():
            self._links[old] = None
        return True

    def _modify(self, mm: Move, k: int) -> bool:
        """MOVEMODIFY(p) at sequencing: change the end of the axis' last buffered single-axis
        linear move to ``p`` (consumed: True), else it loads as a move of its own (spec
        §10.2: MC4 help text; the MC2xx page was not reachable). A new end behind the
        executing move's present position cancels it at DECEL first (same source)."""
        ax = self.axes[mm.axes[0]]
        target = ax.last_buffered()
        if (
            target is None or len(target.axes) != 1 or target.cancelled
            or target.geom not in ("MOVE", "MOVEABS") or target.merged_into is not None
        ):
            return False
        p = mm.args[0]
        if target.start_tick is None:  # in NTYPE: it will run to p from wherever it starts
            target.geom, target.args = "MOVEABS", (p,)
            self.log.emit("move_modify", axis=ax.n, mtype=target.mtype, end=p)
            return True
        t = self.clock.t(k)
        tau = t - target.t_start
        assert target.profile is not None
        here = target.positions(tau)[0]
        if (p - here) * target.unit[0] < 0.0 or (p == here and target.profile.v(tau) > 0.0):
            self.cancel(ax.n)
            return False
        target.replan(tau, k, t, [ax], end=p)
        self._reschedule_end(target, k)
        self._arm_limits(target, k)
        self.log.emit("move_modify", axis=ax.n, mtype=target.mtype, end=p)
        return True

    def cancel_next(self, axis: int) -> None:
        """CANCEL(1): drop the move waiting in NTYPE of ``axis`` (and its group)."""
        m = self.axes[axis].ntype
        if m is None:
            return
        self._ntype.remove(m)
        self._merged_from.pop(m, None)
        for a in m.axes:
            ax = self.axes[a]
            ax.unbuffer(m)
            self._changed(ax)
        self._kick()

    def rapidstop(self, mode: int = 0) -> None:
        """RAPIDSTOP: CANCEL on every axis at once; the moves buffered in NTYPE and the process
        buffers then load as after any CANCEL. ``RAPIDSTOP(2)`` also empties every NTYPE and
        process buffer first, so nothing runs after the stop.

        The TRM page was not reachable (searched pages/docs for the MC206 RAPIDSTOP entry);
        evidence ``[INF]``: a production pause program issues RAPIDSTOP twice and then CANCEL
        three times, i.e. one RAPIDSTOP leaves buffered moves that load; an MC4 template
        writes ``RAPIDSTOP(2)`` for "stop all motion" (spec §10.10).
        """
        if mode == 2:
            for p in sorted(self.process_buffer):
                self._pb_take(p)
            while self._ntype:
                self.cancel_next(self._ntype[0].axes[0])
        for m in list(self._active):
            self.cancel(m.axes[0])

    def step_demand(self, axis: int, value: float) -> None:
        """ENDMOVE written: with no move in progress on ``axis`` the demand position steps to
        ``value`` (on its nearest whole edge) at once (TRM p. 8-159, DPOS: "a value can be
        forced to create a step change in position by writing to the ENDMOVE parameter if no
        moves are currently in progress on the axis"); with one in progress it is the
        run-time error ``[INF]`` (the TRM gives the write no other meaning)."""
        ax = self.axes[axis]
        if ax.mtype is not None or ax.ntype is not None or ax.queued:
            raise BasicError(f"ENDMOVE AXIS({axis}) can only be written while no move is in "
                             "progress on the axis")
        target = nearest_edge(value, ax.units)
        ax.pos += target - ax.wrap(ax.position())
        self.log.emit("endmove", axis=axis, dpos=ax.dpos())

    # -- the servo period ------------------------------------------------------------------

    def _tick_at(self, k: int) -> None:
        ticks = self._ticks
        if k in ticks:
            return
        ticks.add(k)
        # schedule_at; the period rides on the event (no partial: one allocation less)
        urgent_at(self.env, self.clock.t(k), self._on_servo).k = k

    def _kick(self) -> None:
        """Something may move on at the next servo period: make sure that period runs."""
        if self._can_progress():
            self._tick_at(self.clock.after(self.env.now))

    def _can_progress(self) -> bool:
        axes = self.axes
        for m in self._ntype:
            ms = m.axes
            if len(ms) == 1:
                ax = axes[ms[0]]
                if ax.mtype is None and ax.ntype is m:
                    return True
            elif all(axes[a].mtype is None and axes[a].ntype is m for a in ms):
                return True
        depth = self.depth
        for m in self.process_buffer.values():
            ms = m.axes
            if depth == 1:
                if (axes[ms[0]].ntype is None if len(ms) == 1
                        else all(axes[a].ntype is None for a in ms)):
                    return True
            elif all(axes[a].buffered() < depth for a in ms):
                return True
        if self._links or self._offsets or self._guards_busy():
            return True
        return any(q and p not in self.process_buffer for p, q in self._waiters.items())

    def _servo(self, event: Any) -> None:
        """Servo period ``k`` (the interrupt's event, queued by :meth:`_tick_at`, carries
        it): the steps of the module docstring."""
        k: int = event.k
        self._ticks.discard(k)
        if self._dead:
            return
        axes = self.axes
        if self._offsets:
            self._apply_offsets(k)
        # 1. sequencing: process buffers -> NTYPE (all the move's axes or none)
        pb = self.process_buffer
        if pb:
            for p in sorted(pb) if len(pb) > 1 else list(pb):
                m = pb[p]
                ms = m.axes
                if (m.kind == "MOVEMODIFY" and self._modify(m, k)) or (
                    m.kind == "CONNECT" and self._reconnect(m, k)
                ):
                    self._pb_take(p)
                    continue
                if (axes[ms[0]].ntype is None if len(ms) == 1
                        else all(axes[a].ntype is None for a in ms)) or (
                        self.depth > 1 and all(axes[a].buffered() < self.depth for a in ms)):
                    self._pb_take(p, False)
                    if (axes[ms[0]].mtype is None and axes[ms[0]].ntype is None
                            if len(ms) == 1 else
                            all(axes[a].mtype is None and axes[a].ntype is None for a in ms)):
                        # NTYPE and MTYPE free: sequenced and loaded in this same interrupt;
                        # the zero-length stay in NTYPE is not reported as a change
                        self._row("process_buffer", PROCESS_BUFFER_KEYS, (p, m.axes[0], 0))
                        self._active[m] = None
                        for a in m.axes:
                            axes[a].mtype = m
                            self._changed(axes[a])
                        self._begin(m, k)
                        continue
                    self._ntype.append(m)
                    for a in m.axes:
                        axes[a].buffer(m)
                        self._changed(axes[a])
                    self._row("process_buffer", PROCESS_BUFFER_KEYS, (p, m.axes[0], 0))
                    if axes[m.axes[0]].merge and axes[m.axes[0]].ntype is m:
                        self._try_merge(m)
        # 2. move loading: NTYPE -> MTYPE, the move starts now
        if self._ntype:
            for m in list(self._ntype):
                ms = m.axes
                if (axes[ms[0]].mtype is None and axes[ms[0]].ntype is m if len(ms) == 1 else
                        all(axes[a].mtype is None and axes[a].ntype is m for a in ms)):
                    self._ntype.remove(m)
                    self._active[m] = None
                    for a in m.axes:
                        ax = axes[a]
                        ax.unbuffer(m)
                        ax.mtype = m
                        self._changed(ax)
                    self._begin(m, k)
        # 3. the MTYPE moves advance: a software limit hit now ramps its move down; those whose
        # profile is complete end now (a CAMBOX or MOVELINK when its link axis has covered the
        # link distance)
        if self._limit_at or self._limit_watch or self._fe_watch:  # a guard armed (guards.py)
            self._guards_due(k)
        if self._links:
            t = self.clock.t(k)
            for lm in list(self._links):
                if lm.start_tick is not None and lm.start_tick >= k:
                    continue  # started in this period: first looked at in the next
                what = lm.tick(t)
                if what is None:
                    continue
                del self._links[lm]
                if what == "end":
                    lm.finish_at(t - lm.t_start)
                    lm.end_tick = k
                    self._ending.setdefault(k, []).append(lm)
        ending = self._ending.pop(k, ())
        for m in ending:
            del self._active[m]
            nxt = m.merged_into
            final = m.final_positions()
            for i, a in enumerate(m.axes):
                ax = axes[a]
                f, u = final[i], ax.units
                e = f * u
                ax.pos = f if e % 1.0 == 0.0 else nearest_edge(f, u)  # at rest on a whole edge
                ax.mtype = None
                self._row("move_end", MOVE_KEYS, (a, m.mtype))
            linked_next = None if type(m) is Move else self._link_successor(m)
            if linked_next is not None or (
                    nxt is not None and m.profile is not None and axes[m.axes[0]].ntype is nxt):
                if linked_next is not None:
                    # consecutive CAMBOX / MOVELINK on one link axis run as one profile
                    # (MOVELINK-MD example 5): the next goes on from the link position this
                    # one ended at, in the same servo period
                    nxt = linked_next
                else:
                    # MERGE: the next move takes over in this same servo period, from the
                    # exact instant this one's profile ended, at its end speed: MTYPE,
                    # VP_SPEED and MSPEED never read a stop at the joint while the axes run on
                    assert m.profile is not None
                    self._merged_from[nxt] = (m.t_start + m.profile.duration, m.profile.v_end)
                self._ntype.remove(nxt)
                self._active[nxt] = None
                for a in nxt.axes:
                    axes[a].unbuffer(nxt)
                    axes[a].mtype = nxt
                for a in m.axes:
                    self._changed(axes[a])
                self._begin(nxt, k)
                if linked_next is not None:
                    linked_next.continue_from(m)
                continue
            for a in m.axes:
                self._changed(axes[a])
        # 4. processes waiting at a move line: their move goes into the freed buffer
        if self._waiters:
            pb = self.process_buffer
            waiters = self._waiters
            for p in sorted(waiters) if len(waiters) > 1 else list(waiters):
                q = waiters[p]
                while q and p not in pb:
                    w = q.popleft()
                    if not w.alive:
                        continue
                    placed = self.place(w.move, k + 1)
                    assert placed is not None
                    w.alive = False
                    if w.resume:
                        self._resumes.append(w.on_placed)
                    else:
                        w.on_placed(placed)
                if not q:
                    del waiters[p]
        if k + 1 not in self._ticks and self._can_progress():
            self._tick_at(k + 1)
        if self._resumes:
            self._resume_placed()

    def _begin(self, m: Move, k: int) -> None:
        ms = m.axes
        axes = [self.axes[ms[0]]] if len(ms) == 1 else [self.axes[a] for a in ms]
        prev = self._merged_from.pop(m, None) if self._merged_from else None
        if prev is None:
            m.begin(k, self.clock.t(k), axes)
        else:
            m.begin(k, prev[0], axes, prev[1])
        prof = m.profile
        assert prof is not None
        row = self._row
        for a in ms:
            row("move_start", MOVE_KEYS, (a, m.mtype))
        if prof.duration != math.inf:
            if prev is None:
                self._end_at(m, k + max(1, self.clock.cycles(prof.duration)))
            else:
                self._end_merged(m)
        base = axes[0]
        if base.merge and base.ntype is not None:
            self._try_merge(base.ntype)
        if type(m) is not Move and m.needs_tick():
            self._links[m] = None
        self._guard_move(m, k, axes)

    def _link_successor(self, m: Move) -> LinkedMove | None:
        """The CAMBOX / MOVELINK waiting in NTYPE behind the CAMBOX / MOVELINK ``m`` that ended
        by its link distance, on the same link axis (None: no such joint)."""
        if not isinstance(m, LinkedMove) or m.run is None or m.cancelled:
            return None
        nxt = self.axes[m.axes[0]].ntype
        if (isinstance(nxt, LinkedMove) and nxt.kind in ("CAMBOX", "MOVELINK")
                and nxt.link is m.link and nxt.axes == m.axes):
            return nxt
        return None

    def _end_merged(self, m: Move) -> None:
        """Schedule the end of a move whose profile origin is not its start cycle."""
        assert m.profile is not None and m.start_tick is not None
        end = self.clock.at_or_after(m.t_start + m.profile.duration)
        self._end_at(m, max(m.start_tick + 1, end))

    def _try_merge(self, nxt: Move) -> None:
        """MERGE: ``nxt`` has just entered NTYPE; let the MTYPE move run into it at speed."""
        axes = self.axes
        base = axes[nxt.axes[0]]
        m = base.mtype
        if (
            m is None or not base.merge or m.start_tick is None or m.cancelled
            or m.merged_into is not None or m.axes != nxt.axes
            or m.kind not in MERGEABLE or nxt.kind not in MERGEABLE
        ):
            return
        assert m.profile is not None
        tau = self.clock.t(self.clock.index(self.env.now)) - m.t_start
        merged = m.merged_profile()
        if tau > diverges_at(m.profile, merged) + 1e-12:
            return  # the ramp down has begun: too late to merge
        m.profile = merged
        m.merged_into = nxt
        self._end_merged(m)

    def _end_at(self, m: Move, k: int) -> None:
        if m.end_tick is not None:
            old = self._ending.get(m.end_tick)
            if old and m in old:
                old.remove(m)
        m.end_tick = k
        self._ending.setdefault(k, []).append(m)
        self._tick_at(k)


__all__ = ["MotionBuffers", "Waiter", "schedule_at"]
