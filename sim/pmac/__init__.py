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

The package's names below are its public surface, what ``api/`` may import (a test checks it):
the controller, the compiled line and PLC program a REST body is checked against, the SRM
meaning of an ``ERRnnn`` code and the PLC listing.
"""

from .buffers.program import compile_line
from .card.error_codes import meaning
from .controller import MAX_LINE_CHARS, LoadResult, PmacController
from .host.listing import stored_entries
from .language.compiled import ProgramLine
from .tasks.plc import PlcProgram, compile_plc

__all__ = [
    "MAX_LINE_CHARS", "LoadResult", "PlcProgram", "PmacController", "ProgramLine", "compile_line",
    "compile_plc", "meaning", "stored_entries",
]  # fmt: skip
