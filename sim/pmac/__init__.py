"""The Delta Tau Turbo PMAC kind: rotary program buffers, BREQ, lookahead, sync M-variables.

Modules, one idea each: ``statements`` (typed statements), ``parser`` (text -> statements),
``expressions`` (PMAC arithmetic), ``program`` (a stored line: ops and words), ``variables``
(I/P/Q/M), ``rotary`` (the ring of words; BREQ is decided there and only there), ``motion``
(move timing and profiles), ``lookahead`` (per-CS planning at RTIs and execution),
``scheduler`` (servo / RTI instants), ``cpu`` (processor time: RTI, PLC 0, background
cycle), ``watchdog``, ``plc`` (PLC programs), ``terminal`` (on-line command dispatch per
port), ``controller`` (``PmacController``).
"""

from motionsim.sim.pmac.controller import LoadResult, PmacController

__all__ = ["LoadResult", "PmacController"]
