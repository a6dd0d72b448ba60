"""The Delta Tau Turbo PMAC kind: rotary program buffers, BREQ, lookahead, sync M-variables.

Sub-packages, one concern each (``docs/DESIGN.md`` argues the grouping):

* ``language`` — text to typed statements: parser, statements, expressions, the fast path,
  the PLC parser;
* ``card`` — variables, I-variable rules, factory defaults, M-variable definitions and card
  memory, registers, ``SAVE`` / ``$$$``, error codes;
* ``tasks`` — servo / RTI instants, the CPU model, the watchdog, PLC programs;
* ``motor`` — servo-loop state, jog / home, the ``#n?`` status words;
* ``buffers`` — rotary and fixed program buffers, stored lines, ``PC`` / ``PE``, the special
  lookahead buffer, line numbering, move timing;
* ``host`` — the command line of a port: dispatch, control characters, listings, the
  not-simulated table;
* ``lookahead`` (per-CS planning and execution) and ``modes`` (one module a move mode);
* ``controller`` — ``PmacController``, which composes them.
"""

from motionsim.sim.pmac.controller import LoadResult, PmacController

__all__ = ["LoadResult", "PmacController"]
