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

#: Axis parameters only stored (and their power-up values): :mod:`motionsim.sim.trio.axis_status`.
AXIS_STORED = frozenset(
    {"FS_LIMIT", "RS_LIMIT", "ERRORMASK", "FE_LIMIT", "FE_RANGE", "AXIS_ENABLE", "SERVO",
     "JOGSPEED", "FASTDEC", "ATYPE"}
)

#: Read-only axis parameters computed from the motion: AXISSTATUS (the bits the simulation
#: knows); MSPEED = the demand speed, as MPOS = DPOS (no following error, ``[INF]``); VPSPEED
#: the other spelling of VP_SPEED ``[BK]``.
AXIS_COMPUTED = frozenset({"AXISSTATUS", "MSPEED", "VPSPEED"})

AXIS_PARAMS = AXIS_WRITABLE | AXIS_READONLY | AXIS_STORED | AXIS_COMPUTED

#: Process parameters: PMOVE = 1 while the process buffer holds a move; PROCNUMBER = own number;
#: PROC_STATUS 0 = not running, 1 = running; OUTDEVICE = PRINT's channel (writable).
#: RUN_ERROR / ERROR_LINE: the last run-time error of the process and its line (0 = none).
PROCESS_PARAMS = frozenset(
    {"PMOVE", "PROCNUMBER", "PROC_STATUS", "OUTDEVICE", "RUN_ERROR", "ERROR_LINE"}
)
PROCESS_WRITABLE = frozenset({"OUTDEVICE"})

#: System parameters (SERVO_PERIOD in microseconds, read-only here; TICKS ms since power-up
#: counting up — the real controller's TICKS counts down and is writable, not modelled).
#: The others: :mod:`motionsim.sim.trio.system` (WDOG is the one a program writes).
SYSTEM_PARAMS = frozenset(
    {"SERVO_PERIOD", "WDOG", "VERSION", "CONTROL", "SERIAL_NUMBER", "FREE", "SYSTEM_ERROR",
     "MOTION_ERROR", "ERROR_AXIS"}
)
SYSTEM_WRITABLE = frozenset({"WDOG"})

#: Every parameter a program may write.
WRITABLE = AXIS_WRITABLE | AXIS_STORED | PROCESS_WRITABLE | SYSTEM_WRITABLE

#: Constants readable as names.
CONSTANTS = {"TRUE": -1.0, "FALSE": 0.0, "ON": 1.0, "OFF": 0.0}

ALL_PARAMS = AXIS_PARAMS | PROCESS_PARAMS | SYSTEM_PARAMS

__all__ = [
    "ALL_PARAMS",
    "AXIS_PARAMS",
    "AXIS_COMPUTED",
    "AXIS_READONLY",
    "AXIS_STORED",
    "AXIS_WRITABLE",
    "CONSTANTS",
    "PROCESS_PARAMS",
    "PROCESS_WRITABLE",
    "SYSTEM_PARAMS",
    "SYSTEM_WRITABLE",
    "WRITABLE",
]
