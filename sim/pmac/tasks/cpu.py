"""The Turbo PMAC processor-time model: servo, RTI and background sharing one CPU.

Priorities (seed 003; TUM p236-237, p376; spec §9.3, §9.5, §9.6), highest first:

1. **servo** — every servo cycle, ``servo_base_s + servo_motor_s`` × active motors;
2. **RTI** — every I8+1 servo cycles: move planning (``plan_line_s`` per program line
   calculated since the last RTI, plus ``rti_base_s``), then PLC 0 (``plc_scan_s`` +
   ``plc_statement_s`` per statement executed) when I5 permits and it is enabled, then
   PLCC 0 (``plcc_statement_s`` per statement). The RTI's tasks run only when the previous
   RTI's tasks have finished: an
   RTI that finds them still running is an ``rti_overrun`` (``over_s`` = processor time they
   still need, in seconds of wall time at the current servo load) and is *latched* — its tasks
   (PLC 0 again) run as soon as the previous ones end ``[INF]`` (one-deep interrupt latch). So
   a PLC 0 longer than the RTI period keeps the processor in foreground for good;
3. **background** — whatever is left: a background cycle is one scan of one enabled PLC 1-31
   (in turn, if I5 permits), then one scan of every enabled compiled PLC 1-31 (low to high),
   ``housekeeping_s`` (limits, watchdog reload), and one queued
   host command (``host_command_s``), answered at the end of the cycle.

Time model: a fluid share of the processor. Between two instants the processor time left by
the servo task, ``(1 - servo_load) × dt``, goes first to unfinished RTI work, then to the
current background cycle. Observable instants are quantised: a background cycle ends on the
first servo cycle at or after the moment its work is done (at least ``background_cycles``
servo cycles after its start, default 1) — so at most one background cycle ends per servo
cycle and a lightly loaded card answers a host command one servo cycle after it arrives, as
before this model. A PLC's scan executes (its statements take effect) at the start of its
background cycle or at its RTI; its cost decides when the cycle or the RTI's work ends.

Nothing runs while there is nothing to account: with no PLC enabled, no host command queued and
no RTI work outstanding the model sleeps (the background is free-running housekeeping, the
watchdog reloaded), and the rotary stream's hot path does not touch it. Planning costs are
read lazily from the rotary buffers' line counters at each RTI while the model is awake.

Costs (:class:`CpuCosts`, config keys ``cpu_<name>_us`` in microseconds, e.g.
``{"cpu_plc_statement_us": 5}``) and their basis:

* ``servo_motor`` 4.4 µs — seed 003: at the default 2.25 kHz (442 µs) "the servo update of
  each motor takes approximately 1 %" of the processor;
* ``plc_statement`` 3.3 µs — TSRM p486-489 (spec §10): an interpreted operation takes
  2.9-3.6 µs on an 80 MHz Turbo CPU, so ``P10=P10+1`` costs a few µs and ≈ 400 of them fill
  one default RTI period. Every statement executed counts once (assignment, IF/WHILE test,
  ELSE jump, ENDWHILE, CMD, SEND, ENABLE/DISABLE) ``[INF]``;
* ``plcc_statement`` 1.3 µs — a compiled PLC's statement (TSRM p486-489, spec §10: compiled
  floating point ≈ 1-1.6 µs per operation);
* ``plc_scan`` 5 µs per scan, ``rti_base`` 2 µs per RTI, ``plan_line`` 30 µs per program line
  calculated, ``host_command`` 20 µs per command line, ``housekeeping`` 20 µs per background
  cycle — ``[INF]`` orders of magnitude chosen for a DSP56k at 80-240 MHz; the manual gives
  timer registers (TUM p239-240), not figures.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable, Mapping
from dataclasses import dataclass, fields
from typing import TYPE_CHECKING, Any

from ...simpy_adapter import cancel
from .scheduler import Wake
from .watchdog import Watchdog

if TYPE_CHECKING:
    from ..controller import PmacController
    from .plc import Plc

_EPS = 1e-12
_INF = math.inf


@dataclass(slots=True)
class CpuCosts:
    """Processor time per task, in seconds (see the module docstring for the basis)."""

    servo_motor_s: float = 4.4e-6
    servo_base_s: float = 0.0
    rti_base_s: float = 2e-6
    plan_line_s: float = 30e-6
    plc_scan_s: float = 5e-6
    plc_statement_s: float = 3.3e-6
    plcc_statement_s: float = 1.3e-6
    host_command_s: float = 20e-6
    housekeeping_s: float = 20e-6

    @classmethod
    def from_config(cls, config: Mapping[str, Any]) -> CpuCosts:
        """Defaults overridden by ``cpu_<name>_us`` keys (microseconds)."""
        costs = cls()
        for f in fields(cls):
            key = config_key(f.name)
            if key in config:
                setattr(costs, f.name, float(config[key]) * 1e-6)
        return costs


def config_key(field_name: str) -> str:
    """``plc_statement_s`` -> ``cpu_plc_statement_us``."""
    return "cpu_" + field_name[:-2] + "_us"


#: The config keys this model reads.
CONFIG_KEYS = frozenset(config_key(f.name) for f in fields(CpuCosts))


#: Statements of background PLC scans worked through at one simulated instant: a longer
#: scan goes on at the servo cycle its processor time has run out (it is charged the same
#: time in all), so one scan of a 200 000-character PLC is many short events, not one long
#: one, and a realtime clock slice stays short (issue 33 item 4). Scans below it run as
#: one piece, at the instant they always did.
SCAN_SLICE = 2000

#: In a background cycle's ``todo``: "the active compiled PLCs, low to high", expanded when
#: the interpreted PLC's scan is over (its scan may enable or disable one).
_PLCCS = None


class _BgCycle:
    __slots__ = ("start", "left", "min_end", "plc", "todo")

    def __init__(self, start: float, left: float, min_end: float, plc: int | None,
                 todo: list[Plc | None]) -> None:
        self.start = start
        self.left = left
        self.min_end = min_end
        self.plc = plc
        #: The scans of this cycle still to run: a sliced scan in progress first.
        self.todo = todo


class Processor:
    """Runs the RTI's PLC 0 and the background cycle on a shared processor-time budget.

    ``submit(job)`` queues a host command, answered at the
    end of a background cycle; :meth:`poke` tells it that something changed (a PLC enabled,
    I5 or I8 written). Owned by :class:`motionsim.sim.pmac.controller.PmacController`.
    """

    def __init__(self, ctl: PmacController, cycle_cycles: int = 1) -> None:
        self.ctl = ctl
        self.env = ctl.env
        self.scheduler = ctl.scheduler
        self.clock = ctl.scheduler.clock
        self.costs = CpuCosts.from_config(ctl.config)
        self._min_cycles = max(1, int(cycle_cycles))
        self.queue: deque[Callable[[], None]] = deque()
        self.power_on()

    def power_on(self) -> None:
        """Fresh state (construction and reset)."""
        self._cancel()
        self.queue.clear()
        self.watchdog = Watchdog(self.ctl)
        self.cycles = 0
        self.last_cycle_s: float | None = None
        #: Simulated instant the last background cycle (one with a host command or a PLC
        #: 1-31 scan) completed; None before the first.
        self.last_background_s: float | None = None
        self._active = False
        self._in_wake = False
        self._scanning = False  # a background PLC scan is being worked through
        self._t = self.env.now
        self._fg = 0.0  # RTI work left, processor seconds
        self._latched = False
        self._bg: _BgCycle | None = None
        self._next_rti = _INF
        self._lines_seen = 0
        self.rti_overruns = 0
        self.plc0_scans = 0
        self._win = [self.env.now, 0.0]  # window start, RTI work done in it
        self._last_rti_share: float | None = None
        self._stall = (-_INF, -_INF)  # an injected stall: the background gets nothing in it

    # -- host commands and changes ---------------------------------------------------------

    def submit(self, job: Callable[[], None]) -> None:
        """Queue a host command (executed at the end of a background cycle)."""
        self.queue.append(job)
        self.poke()

    def poke(self) -> None:
        """Something changed now: account the time so far and re-plan the next wake-up."""
        if self._in_wake or self._scanning or self.watchdog.tripped:
            return
        if self._active:
            self._advance(self.env.now)
        self._schedule()

    def stall(self, start: float, end: float) -> None:
        """Starve the background from ``start`` to ``end`` (simulated seconds), an injected
        fault (:mod:`motionsim.sim.faults`): no host command is answered, no PLC 1-31 scans
        and the watchdog is not reloaded in that window; the servo and RTI tasks go on."""
        self._stall = (start, end)
        self.poke()

    def _bg_time(self, a: float, b: float) -> float:
        """Wall time of ``[a, b]`` outside the stall window (what the background may use)."""
        s0, s1 = self._stall
        return (b - a) - max(0.0, min(b, s1) - max(a, s0))

    @property
    def active(self) -> bool:
        """Busy with RTI / background work (not free-running housekeeping)."""
        return self._active

    # -- loads ------------------------------------------------------------------------------

    def servo_s(self) -> float:
        """Processor time of one servo cycle: per active motor (assigned to an axis)."""
        c = self.costs
        return c.servo_base_s + c.servo_motor_s * len(self.ctl.motors)

    def _rate(self) -> float:
        """Share of the processor left to RTI and background tasks."""
        return max(0.0, 1.0 - self.servo_s() / self.clock.period_s)

    def _lines_calculated(self) -> int:
        total = 0
        for c in self.ctl.coord_systems.values():
            rot = c.rotary
            if rot is not None:
                total += rot.n_loaded - len(rot.pending)
        return total

    # -- scheduling -------------------------------------------------------------------------

    def _cancel(self) -> None:
        cancel(getattr(self, "_wake", None))
        self._wake: Wake | None = None

    def _wanted(self) -> bool:
        plcs = self.ctl.plcs
        return bool(
            self.queue
            or self._bg is not None
            or self._fg > _EPS
            or self._latched
            or plcs.foreground() is not None
            or plcs.foreground_compiled() is not None
            or plcs.any_background()
            or self._stall[1] > self.env.now
        )

    def _schedule(self) -> None:
        now = self.env.now
        self._cancel()
        if self.watchdog.tripped:
            return
        if not self._wanted():
            self._active = False
            return
        if not self._active:
            # Waking from free-running housekeeping: the watchdog was just reloaded.
            self._active = True
            self._t = now
            self._fg = 0.0
            self._latched = False
            self.watchdog.reload(now)
            self._lines_seen = self._lines_calculated()
            self._next_rti = self.scheduler.next_rti_after(now)
            self._win = [now, 0.0]
        if self._bg is None and (self.queue or self.ctl.plcs.any_background()):
            self._start_bg(now)
        r = self._rate()
        t_next = min(self._next_rti, self.watchdog.deadline())
        if r > 0:
            if self._latched:
                t_next = min(t_next, self.scheduler.servo_at_or_after(now + max(0.0, self._fg) / r))
            bg = self._bg
            if bg is not None:
                work = max(0.0, self._fg) + bg.left
                done = now + work / r
                s0, s1 = self._stall
                if s1 > now and s0 < done:
                    done += s1 - max(now, s0)  # the stall holds the background back
                t_bg = self.scheduler.servo_at_or_after(done)
                if not bg.todo:
                    t_bg = max(t_bg, bg.min_end)
                t_next = min(t_next, t_bg)
            elif self._stall[0] > now:
                t_next = min(t_next, self.scheduler.servo_at_or_after(self._stall[0]))
        if self._stall[0] <= now < self._stall[1]:
            t_next = min(t_next, max(self._stall[1], now))
        self._wake = Wake(self.env, max(t_next, now), self._on_wake)

    def _advance(self, t: float) -> None:
        """Give the processor time of ``[self._t, t]`` to RTI work, then background."""
        dt = t - self._t
        if dt <= 0:
            return
        r = self._rate()
        cap = dt * r
        # Latched: the next RTI's tasks start the moment these end, so the foreground keeps
        # the processor (``_fg`` goes below 0: work already done for the latched tasks).
        use = cap if self._latched else min(self._fg, cap)
        self._fg -= use
        cap -= use
        self._win[1] += use
        if self._stall[1] > self._t:
            cap = min(cap, self._bg_time(self._t, t) * r)
        bg = self._bg
        if bg is not None:
            bg.left = max(0.0, bg.left - cap)
        elif r > 0 and cap > _EPS and cap >= self.costs.housekeeping_s:
            # Free-running housekeeping cycles reload the watchdog once RTI work is done (and
            # only with processor time left for them: at a zero housekeeping cost too).
            done = self._t + (use + self.costs.housekeeping_s) / r
            self.watchdog.reload(min(t, self.scheduler.servo_at_or_after(done)))
        self._t = t
        if t - self._win[0] >= 1.0:
            self._last_rti_share = self._win[1] / (t - self._win[0])
            self._win = [t, 0.0]

    def _on_wake(self, _ev: Any) -> None:
        self._wake = None
        now = self.env.now
        self._advance(now)
        if now >= self.watchdog.deadline() - 1e-9:
            self._trip()
            return
        self._in_wake = True
        try:
            if self._latched and self._fg <= _EPS:
                self._latched = False
                self._fg = max(0.0, self._fg + self._plc0())
            if now >= self._next_rti - 1e-9:
                self._rti(now)
                self._next_rti = self.scheduler.next_rti_after(now)
            bg = self._bg
            if bg is not None and bg.left <= _EPS and bg.todo:
                # the next slice of a long scan; a PLC disabled meanwhile is left out
                bg.todo = [p for p in bg.todo if p is None or p.enabled]
                bg.left += self._run_scans(bg.todo)
            if bg is not None and bg.left <= _EPS and not bg.todo \
                    and now >= bg.min_end - 1e-9:
                self._end_bg(now)
        finally:
            self._in_wake = False
        if not self.watchdog.tripped:
            self._schedule()

    # -- the tasks ----------------------------------------------------------------------------

    def _rti(self, now: float) -> None:
        """One real-time interrupt: planning work, then PLC 0 unless the last RTI overran."""
        c = self.costs
        lines = self._lines_calculated()
        planning = c.rti_base_s + c.plan_line_s * max(0, lines - self._lines_seen)
        self._lines_seen = lines
        if self._fg > _EPS:
            r = self._rate()
            self.rti_overruns += 1
            self.ctl.log.emit("rti_overrun", over_s=self._fg / r if r > 0 else _INF)
            self._latched = True
            self._fg += planning
            return
        self._fg += planning + self._plc0()

    def _plc0(self) -> float:
        plcs = self.ctl.plcs
        plc = plcs.foreground()
        cost = 0.0
        if plc is not None:
            self.plc0_scans += 1
            cost = self._scan_cost(plcs.scan(plc))
        plcc = plcs.foreground_compiled()  # PLCC 0 runs after PLC 0 (TUM p376)
        if plcc is not None:
            cost += self._compiled_cost(plcs.scan(plcc))
        return cost

    def _compiled_cost(self, statements: int) -> float:
        return self.costs.plc_scan_s + self.costs.plcc_statement_s * statements

    def _scan_cost(self, statements: int) -> float:
        return self.costs.plc_scan_s + self.costs.plc_statement_s * statements

    def _start_bg(self, now: float) -> None:
        clock = self.clock
        k = clock.index(now)
        plcs = self.ctl.plcs
        plc: Plc | None = None
        if abs(now - clock.t(k)) < 1e-9:
            plc = plcs.next_background()
        # else: waking between servo cycles, the free-running housekeeping pass in progress
        # answers; PLC scans start with the next cycle (every instant stays on a servo cycle).
        work = self.costs.housekeeping_s
        todo: list[Plc | None] = [] if plc is None else [plc]
        if abs(now - clock.t(k)) < 1e-9:
            todo.append(_PLCCS)  # between two interpreted-PLC scans: every active PLCC
        work += self._run_scans(todo)
        if self.queue:
            work += self.costs.host_command_s
        self._bg = _BgCycle(clock.t(k), work, clock.t(k + self._min_cycles),
                            plc.n if plc else None, todo)

    def _run_scans(self, todo: list[Plc | None]) -> float:
        """Work through the background cycle's scans, :data:`SCAN_SLICE` statements at most
        (the rest stays in ``todo``); returns the processor time they take. A scan is
        charged its start once (``plc_scan_s``) and each statement it runs."""
        plcs = self.ctl.plcs
        c = self.costs
        budget = SCAN_SLICE
        work = 0.0
        # A CMD"..." in the scan queues a command (``submit`` -> ``poke``); it must not
        # re-plan (and re-scan) from inside this scan: the queue is charged by the caller.
        self._scanning = True
        try:
            while todo and budget > 0:
                plc = todo[0]
                if plc is None:  # _PLCCS
                    todo[0:1] = plcs.background_compiled()
                    continue
                fresh = not plc.mid_scan
                n = plcs.scan(plc, budget)
                budget -= n
                per = c.plcc_statement_s if plcs.compiled[plc.n] is plc else c.plc_statement_s
                work += (c.plc_scan_s if fresh else 0.0) + per * n
                if plc.mid_scan:
                    break
                todo.pop(0)
        finally:
            self._scanning = False
        return work

    def _end_bg(self, now: float) -> None:
        bg = self._bg
        assert bg is not None
        self._bg = None
        self.cycles += 1
        self.last_cycle_s = now - bg.start
        self.last_background_s = now
        self.watchdog.reload(now)
        if self.queue:
            self.queue.popleft()()

    def _trip(self) -> None:
        self._cancel()
        self._active = False
        self.queue.clear()
        self._bg = None
        self.watchdog.trip()

    # -- reports ----------------------------------------------------------------------------

    def global_status_word1(self) -> int:
        """First word of ``???``: bit 9 "real-time interrupt warning" once an RTI's tasks took
        longer than one RTI period (TSRM p290; latched until reset ``[INF]``)."""
        return (1 << 9) if self.rti_overruns else 0

    def load(self) -> dict[str, float]:
        """``{"servo", "rti", "background", "background_cycle_s"}``: shares of the processor
        (background = what servo and RTI leave, idle time included) over the last full second
        awake (else so far); the last background cycle's length."""
        period = self.clock.period_s
        servo = min(1.0, self.servo_s() / period)
        rti = 0.0
        if self._active:
            if self._last_rti_share is not None:
                rti = self._last_rti_share
            elif self._t > self._win[0]:
                rti = self._win[1] / (self._t - self._win[0])
        rti = min(rti, 1.0 - servo)
        if self._active and self.last_cycle_s is not None:
            cycle = self.last_cycle_s
        else:
            cycle = self._min_cycles * period
        return {
            "servo": servo,
            "rti": rti,
            "background": max(0.0, 1.0 - servo - rti),
            "background_cycle_s": cycle,
        }


__all__ = ["CONFIG_KEYS", "CpuCosts", "Processor", "config_key"]
