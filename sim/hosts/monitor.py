"""A scenario's instrument: the PMAC's processor load sampled into the event log.

The processor-time model (:mod:`motionsim.sim.pmac.tasks.cpu`) reports its load on request only
(``status()["cpu"]``: servo, RTI and background shares, the last background cycle's length).
A run's metrics read the event log alone, so :class:`CpuMonitor` asks every ``period_s`` and
appends a ``cpu_sample`` event — as a host polling the load would, but without going through
the card's command line (it costs the simulated card nothing). It is not a controller event
and never appears on a real card.

``cpu_sample`` fields: ``servo``, ``rti``, ``background`` (shares of the processor),
``background_cycle_s``, and ``plc0_statements`` (statements PLC 0 executed in its last scan, 0
when PLC 0 is not enabled). Sampling stops when the watchdog trips (the card is stopped; its
load figures no longer mean anything).
"""

from __future__ import annotations

from collections.abc import Generator
from typing import Any


class CpuMonitor:
    """Samples ``controller.status()["cpu"]`` on a fixed grid ``t0 + k * period_s``."""

    def __init__(self, controller: Any, period_s: float) -> None:
        if not period_s > 0:
            raise ValueError("period_s must be > 0")
        self.controller = controller
        self.env = controller.env
        self.log = controller.log
        self.period_s = period_s
        self.samples = 0
        self.process: Any = None

    def start(self) -> None:
        self.process = self.env.process(self._run())

    def _plc0_statements(self) -> int:
        plcs = getattr(self.controller, "plcs", None)
        if plcs is None:
            return 0
        p = plcs.plc(0)
        return int(p.last_statements) if p.enabled and p.scans else 0

    def _run(self) -> Generator[Any, Any, None]:
        env = self.env
        t0 = env.now
        k = 0
        while not getattr(self.controller, "halted", False):
            k += 1
            yield env.timeout(t0 + k * self.period_s - env.now)
            if getattr(self.controller, "halted", False):
                return
            cpu = self.controller.status()["cpu"]
            self.samples += 1
            self.log.emit(
                "cpu_sample",
                servo=cpu["servo"],
                rti=cpu["rti"],
                background=cpu["background"],
                background_cycle_s=cpu["background_cycle_s"],
                plc0_statements=self._plc0_statements(),
            )


__all__ = ["CpuMonitor"]
