"""Host models for what-if scenarios: programs on the PC that feed a controller.

Pure SimPy processes (simpy + stdlib ``random``, seeded) that run on the controller's own
environment and use only the controller's public methods and event log, as host software
does. See :mod:`motionsim.sim.hosts.pmac` (rotary-buffer writers) and
:mod:`motionsim.sim.hosts.trio` (move feeders); delays come from
:mod:`motionsim.sim.hosts.distributions`; :mod:`motionsim.sim.hosts.monitor` samples a PMAC's
processor load into the log.
"""

from .distributions import Delay, empirical, fixed
from .monitor import CpuMonitor
from .pmac import BreqInterruptHost, NaiveHost, PmacHost, PrPollingHost
from .trio import BlindFeeder, Move, MovesBufferedFeeder, NtypeFeeder, TrioFeeder

__all__ = [
    "BlindFeeder",
    "BreqInterruptHost",
    "CpuMonitor",
    "Delay",
    "Move",
    "MovesBufferedFeeder",
    "NaiveHost",
    "NtypeFeeder",
    "PmacHost",
    "PrPollingHost",
    "TrioFeeder",
    "empirical",
    "fixed",
]
