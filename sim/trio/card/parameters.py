"""The parameter names Trio BASIC knows, and which of them a program may write.

Axis parameters act on the process' BASE axis unless ``AXIS(n)`` follows the name
(``SPEED AXIS(1)=100``, ``? NTYPE AXIS(0)``). Process parameters take ``PROC(n)``
(``PMOVE PROC(3)``); without it they read the process itself. System parameters have neither.

The stored axis parameters and the start-up / drive parameters are **data**: one
:class:`Stored` row each in :data:`STORED` (power-up value, range, what the simulator does
with it, source), from which the name sets below, ``StoredParams`` and the table of
``docs/trio.md`` are built.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class Stored:
    """One stored axis parameter.

    Attributes:
        name: the BASIC name.
        power_up: the value at power-up.
        low: the smallest value accepted (``None``: any).
        kind: ``"float"``, ``"int"`` (truncated on write), ``"switch"`` (non-zero reads 1) or
            ``"edges"`` (held in whole encoder edges: INT(value x UNITS), read back / UNITS;
            the count stays when UNITS changes).
        writable: False for a parameter only the controller sets (read-only in BASIC).
        effect: what the simulation does with it (``docs/trio.md``); ``"stored"`` when it
            only keeps the value.
        source: the spec section / manual page of the fact, ``[BK]`` / ``[INF]`` where marked.
    """

    name: str
    power_up: float
    low: float | None = None
    kind: str = "float"
    writable: bool = True
    effect: str = "stored"
    source: str = ""


#: The stored axis parameters, start-up and drive parameters included (spec §10.11, §11.5).
STORED: tuple[Stored, ...] = (
    Stored("FS_LIMIT", 200_000_000.0,
           effect="a move reaching it ramps down at DECEL and is cancelled; AXISSTATUS bit 9 "
                  "when DPOS >= it", source="M216-367; power-up [BK]"),
    Stored("RS_LIMIT", -200_000_000.0,
           effect="a move reaching it ramps down at DECEL and is cancelled; AXISSTATUS bit 10 "
                  "when DPOS <= it", source="M216-367; power-up [BK]"),
    Stored("ERRORMASK", 268.0, 0.0, "int", source="spec §10.11 [BK]"),
    Stored("FE_LIMIT", 2000.0, 0.0, source="M216-367 (SERVO); power-up [BK]"),
    Stored("FE_RANGE", 0.0, 0.0, source="spec §10.11 [BK]"),
    Stored("AXIS_ENABLE", 1.0, kind="switch", source="MC4xx name [BK]"),
    Stored("SERVO", 0.0, kind="switch", source="M216-367"),
    Stored("JOGSPEED", 0.0, 0.0, source="spec §10.11 [BK]"),
    Stored("FASTDEC", 0.0, 0.0, effect="when above 0, the ramp down at a software limit [BK]",
           source="spec §10.11 [BK]"),
    Stored("ATYPE", 0.0, 0.0, "int", source="0 = virtual [INF]"),
    # servo gains: no servo loop is modelled (MPOS follows DPOS exactly)
    Stored("P_GAIN", 1.0, source="M206-363 (TRM p. 8-173): 1.0"),
    Stored("I_GAIN", 0.0, source="M206-355 (TRM p. 8-165): 0"),
    Stored("D_GAIN", 0.0, source="M216-349 (TRM p. 8-159); power-up [BK]"),
    Stored("OV_GAIN", 0.0, source="M206-361 (TRM p. 8-171): 0"),
    Stored("VFF_GAIN", 0.0, source="TJ2P-167 'see also'; power-up [BK]"),
    # drive status and following error: no drive, no following error
    Stored("DRIVE_STATUS", 0.0, writable=False,
           effect="reads 0: no drive with digital communications", source="M216-349"),
    Stored("FE_LATCH", 0.0, writable=False,
           effect="reads 0: no following-error trip is modelled",
           source="3P program usage; meaning [BK]"),
    # homing, repeat distance, clutch
    Stored("DATUM_IN", -1.0, -1.0, "int",
           effect="the datum input of DATUM(3)..(6) (-1: none)",
           source="TJ2P5-247; -1 = none [BK]"),
    Stored("REP_DIST", 200_000_000.0, 0.0, "edges",
           effect="DPOS / MPOS wrap at it (REP_OPTION bit 0: range); held as INT(v x UNITS) "
                  "edges",
           source="TKB-REP; power-up [BK]"),
    Stored("REP_OPTION", 0.0, 0.0, "int",
           effect="bit 0: range 0..REP_DIST; bit 1: end a repeating CAMBOX / MOVELINK",
           source="TKB-REP, CAMBOX-MD, MOVELINK-MD"),
    Stored("CLUTCH_RATE", 0.0, 0.0,
           effect="CONNECT ratio changes ramp at it (ratio per second; 0 = at once)",
           source="TJ2P-71; unit [BK]"),
)

STORED_BY_NAME: dict[str, Stored] = {p.name: p for p in STORED}

#: Axis parameters a program can write (units/s, units/s², edges per user unit).
AXIS_WRITABLE = frozenset(
    {"SPEED", "ACCEL", "DECEL", "UNITS", "CREEP", "MERGE", "SRAMP", "FORCE_SPEED", "OFFPOS",
     "ENDMOVE"}
)

#: Axis parameters that are read-only: the buffers and the profile generator own them.
AXIS_READONLY = frozenset(
    {"MTYPE", "NTYPE", "DPOS", "MPOS", "REMAIN", "IDLE", "VP_SPEED", "MOVES_BUFFERED"}
)

#: Axis parameters only stored (and their power-up values): :data:`STORED`.
AXIS_STORED = frozenset(STORED_BY_NAME)

#: Read-only axis parameters computed from the motion: AXISSTATUS (the bits the simulation
#: knows); MSPEED = the demand speed, as MPOS = DPOS (no following error, ``[INF]``); VPSPEED
#: the other spelling of VP_SPEED ``[BK]``; FE = DPOS - MPOS (0: the simulated servo loop
#: follows exactly); ENCODER the raw encoder count (:mod:`motionsim.sim.trio.card.scaling`).
AXIS_COMPUTED = frozenset({"AXISSTATUS", "MSPEED", "VPSPEED", "FE", "ENCODER"})

AXIS_PARAMS = AXIS_WRITABLE | AXIS_READONLY | AXIS_STORED | AXIS_COMPUTED

#: Process parameters: PMOVE = 1 while the process buffer holds a move; PROCNUMBER = own number;
#: PROC_STATUS 0 = not running, 1 = running; OUTDEVICE = PRINT's channel (writable).
#: RUN_ERROR / ERROR_LINE: the last run-time error of the process and its line (0 = none).
PROCESS_PARAMS = frozenset(
    {"PMOVE", "PROCNUMBER", "PROC_STATUS", "OUTDEVICE", "RUN_ERROR", "ERROR_LINE"}
)
PROCESS_WRITABLE = frozenset({"OUTDEVICE"})

#: System parameters (SERVO_PERIOD in microseconds, read-only here).
#: The others: :mod:`motionsim.sim.trio.card.system` (WDOG and LIMIT_BUFFERED are the ones a
#: program writes).
SYSTEM_PARAMS = frozenset(
    {"SERVO_PERIOD", "WDOG", "VERSION", "CONTROL", "SERIAL_NUMBER", "FREE", "SYSTEM_ERROR",
     "MOTION_ERROR", "ERROR_AXIS", "LIMIT_BUFFERED", "SCOPE_POS"}
)
SYSTEM_WRITABLE = frozenset({"WDOG", "LIMIT_BUFFERED"})

#: Every parameter a program may write.
WRITABLE = (
    AXIS_WRITABLE | frozenset(p.name for p in STORED if p.writable) | PROCESS_WRITABLE
    | SYSTEM_WRITABLE
)

#: Constants readable as names.

ALL_PARAMS = AXIS_PARAMS | PROCESS_PARAMS | SYSTEM_PARAMS

__all__ = [
    "ALL_PARAMS",
    "AXIS_PARAMS",
    "AXIS_COMPUTED",
    "AXIS_READONLY",
    "AXIS_STORED",
    "AXIS_WRITABLE",
    "PROCESS_PARAMS",
    "PROCESS_WRITABLE",
    "STORED",
    "STORED_BY_NAME",
    "SYSTEM_PARAMS",
    "SYSTEM_WRITABLE",
    "Stored",
    "WRITABLE",
]
