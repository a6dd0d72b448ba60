"""The parameter names Trio BASIC knows, and which of them a program may write.

Axis parameters act on the process' BASE axis unless ``AXIS(n)`` follows the name
(``SPEED AXIS(1)=100``, ``? NTYPE AXIS(0)``). Process parameters take ``PROC(n)``
(``PMOVE PROC(3)``); without it they read the process itself. System parameters have neither.
"""

from __future__ import annotations

#: Axis parameters a program can write (units/s, units/s², edges per user unit).
AXIS_WRITABLE = frozenset(
    {"SPEED", "ACCEL", "DECEL", "UNITS", "CREEP", "MERGE", "SRAMP", "FORCE_SPEED", "OFFPOS"}
)

#: Axis parameters that are read-only: the buffers and the profile generator own them.
AXIS_READONLY = frozenset(
    {"MTYPE", "NTYPE", "DPOS", "MPOS", "ENDMOVE", "REMAIN", "IDLE", "VP_SPEED", "MOVES_BUFFERED"}
)

AXIS_PARAMS = AXIS_WRITABLE | AXIS_READONLY

#: Process parameters: PMOVE = 1 while the process buffer holds a move; PROCNUMBER = own number;
#: PROC_STATUS 0 = not running, 1 = running; OUTDEVICE = PRINT's channel (writable).
PROCESS_PARAMS = frozenset({"PMOVE", "PROCNUMBER", "PROC_STATUS", "OUTDEVICE"})
PROCESS_WRITABLE = frozenset({"OUTDEVICE"})

#: System parameters (SERVO_PERIOD in microseconds, read-only here; TICKS ms since power-up
#: counting up — the real controller's TICKS counts down and is writable, not modelled).
SYSTEM_PARAMS = frozenset({"SERVO_PERIOD"})

#: Constants readable as names.
CONSTANTS = {"TRUE": -1.0, "FALSE": 0.0, "ON": 1.0, "OFF": 0.0}

ALL_PARAMS = AXIS_PARAMS | PROCESS_PARAMS | SYSTEM_PARAMS

__all__ = [
    "ALL_PARAMS",
    "AXIS_PARAMS",
    "AXIS_READONLY",
    "AXIS_WRITABLE",
    "CONSTANTS",
    "PROCESS_PARAMS",
    "PROCESS_WRITABLE",
    "SYSTEM_PARAMS",
]
