"""The Turbo PMAC watchdog timer (seed 003; TUM p215, p240; TSRM p57; BHW p41; spec §9.6).

The hardware watchdog needs a steady strobe from the software: every servo interrupt counts a
register down, and the **end of every background cycle** reloads it with I40 servo cycles
(I40 = 0 means the default 4096 ≈ 1.81 s at 442 µs). When no background cycle completes in
that time — a PLC 0 or a servo load that leaves the background no processor time — the timer
trips: the card latches into reset, motors are killed (amplifiers disabled, no deceleration),
programs stop, discrete outputs go off, and the CPU stops and will not communicate. Only a
power cycle (:meth:`sim.pmac.controller.PmacController.reset`) brings it back.

Modelled: the trip instant is the servo cycle ``last_reload + limit`` ``[INF]`` (the
one-cycle difference between "counter reaches 0" and "counter below 0" is not resolved by the
manual text found). On a trip: the motors are killed — every coordinate system's commanded
positions freeze at the trip instant (no deceleration ramp; a moving CS gets its ``move_end``
then), its lookahead is dropped and a running program is aborted with ``error="watchdog"``
(:meth:`sim.pmac.lookahead.CoordSystem.kill`); every M-variable that is not 0 is written 0
(outputs off, ``mvar`` events); a ``watchdog`` event with the ``reason``; from then on the
controller answers nothing (:class:`motionsim.sim.errors.Halted`) and its processor runs no task
until reset.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..controller import PmacController

#: I40 = 0 selects this many servo cycles (TSRM p57: "4095/4096").
DEFAULT_LIMIT_CYCLES = 4096


class Watchdog:
    """The watchdog of one controller: when it was last reloaded, whether it has tripped."""

    def __init__(self, ctl: PmacController) -> None:
        self.ctl = ctl
        self.last_reload = ctl.env.now
        self.tripped = False
        self.t_trip: float | None = None

    def limit_cycles(self) -> int:
        """Servo cycles allowed between background cycles: I40, or 4096 when I40 = 0."""
        i40 = int(self.ctl.vars.I(40))
        return DEFAULT_LIMIT_CYCLES if i40 <= 0 else i40

    def reload(self, t: float) -> None:
        """A background cycle ended at ``t``."""
        if t > self.last_reload:
            self.last_reload = t

    def deadline(self) -> float:
        """The servo-cycle instant the watchdog trips if not reloaded before."""
        clock = self.ctl.scheduler.clock
        return clock.t(clock.at_or_after(self.last_reload) + self.limit_cycles())

    def margin(self, active: bool) -> dict[str, float | int | None]:
        """The reload figures of ``status()``: ``reload_s`` (when the counter was last
        reloaded), ``limit_cycles`` (I40) and ``cycles_left`` (servo cycles from now to the
        trip if no background cycle ends before; 0 once tripped).

        While the processor is idle (``active`` False) the free-running housekeeping cycles
        reload the counter every servo cycle ``[INF]``: ``reload_s`` is then the current servo
        cycle and the whole limit is left. While busy, the figures are as of the processor's
        last accounting (its last wake-up), so ``cycles_left`` is a lower bound.
        """
        clock = self.ctl.scheduler.clock
        now = self.ctl.env.now
        k_now = clock.index(now)
        limit = self.limit_cycles()
        if self.tripped:
            return {"reload_s": self.last_reload, "limit_cycles": limit, "cycles_left": 0}
        if not active:
            return {"reload_s": clock.t(k_now), "limit_cycles": limit, "cycles_left": limit}
        k_trip = clock.at_or_after(self.last_reload) + limit
        return {
            "reload_s": self.last_reload,
            "limit_cycles": limit,
            "cycles_left": max(0, k_trip - k_now),
        }

    def trip(self) -> None:
        """Trip now: kill motors, stop programs, outputs off, ``watchdog`` event, halt."""
        if self.tripped:
            return
        ctl = self.ctl
        self.tripped = True
        self.t_trip = ctl.env.now
        ctl.halted = True
        limit = self.limit_cycles()
        ctl.log.emit(
            "watchdog",
            reason=f"no background cycle completed within {limit} servo cycles (I40)",
        )
        for c in ctl.coord_systems.values():
            c.kill("watchdog")
        ctl.motor_table.kill_all()
        vars_ = ctl.vars
        for n in sorted(k for k, v in vars_.m.items() if v != 0):
            vars_.write("M", n, 0.0)


__all__ = ["DEFAULT_LIMIT_CYCLES", "Watchdog"]
