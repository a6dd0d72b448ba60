"""Trio BASIC constants and the language's own parameters (TICKS, LAST_AXIS).

Constants are read-only names with a fixed value, at the command line and in programs; a
program can never use one as a local variable (writing one is a compile error):

* ``TRUE`` = -1, ``FALSE`` = 0 (M224-327: the comparison operators' results);
* ``ON`` = 1 (TJ2P5-138, ``OP(lever, ON)``), ``OFF`` = 0 ``[INF]``;
* ``PI`` = 3.14159... (TJ2P-167, ``circum/(2*PI)``) at the model's word precision.

The index's later sections (system parameters, constants) were not reachable (spec §11.12), so
this table holds the constants found on the pages above.

Language parameters (spec §11.10):

* ``TICKS`` — a process parameter, read and write, that counts down by 1 every servo period
  (the 3P drivers' ``TICKS = ms*1000/SERVO_PERIOD`` then ``WAIT UNTIL TICKS <= 0``, TRIOQ,
  ``[INF]`` direction and rate); 0 when the process starts ``[INF]``;
* ``LAST_AXIS`` — a read-only system value: the highest axis number (``FOR a = 0 TO
  LAST_AXIS`` in real code, ``[INF]``).
"""

from __future__ import annotations

import math

#: Read-only named values (spec §11.10).
CONSTANTS: dict[str, float] = {
    "TRUE": -1.0,
    "FALSE": 0.0,
    "ON": 1.0,
    "OFF": 0.0,
    "PI": math.pi,
}

#: Parameters of the language itself: name -> (kind, writable).
LANGUAGE_PARAMS: dict[str, tuple[str, bool]] = {
    "TICKS": ("process", True),
    "LAST_AXIS": ("system", False),
}

__all__ = ["CONSTANTS", "LANGUAGE_PARAMS"]
