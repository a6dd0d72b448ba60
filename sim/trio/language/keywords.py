"""The Trio BASIC command index of the TRM, and which of its keywords the simulator runs.

``INDEX`` is chapter 8 of the Motion Coordinator Technical Reference Manual (6th edition,
"Trio BASIC Commands" contents: Motion and Axis Commands, Input / Output Commands, Program
Loops and Structures; docslib "motion-and-axis-commands"), as far as its contents pages could
be read — the later sections of the index (system commands, parameters, constants) were not
reachable. A program using an indexed keyword that is **not** simulated is refused when it is
stored, with the line, the column and "not simulated" (:class:`motionsim.sim.errors.NotSimulated`,
HTTP 501 ``not_simulated``) — not as a syntax error. ``docs/trio.md`` prints this table.
:data:`MC4_WORDS` are the MC4xx / MC6xx language's own words (spec §11), keywords only there.
"""

from __future__ import annotations

from ..card.models import MODELS
from ..card.parameters import STORED
from ..card.setup_commands import COMMANDS

#: TRM chapter 8 contents, by section, in the manual's order.
INDEX: dict[str, tuple[str, ...]] = {
    "Motion and Axis Commands": (
        "ACC", "ADD_DAC", "ADDAX", "AXIS", "BACKLASH", "BASE", "CAM", "CAMBOX", "CANCEL",
        "CONNECT", "DATUM", "DEC", "DEFPOS", "DISABLE_GROUP", "ENCODER_RATIO", "FORWARD",
        "MHELICAL", "MHELICALSP", "MOVE", "MOVEABS", "MOVEABSSP", "MOVECIRC", "MOVECIRCSP",
        "MOVELINK", "MOVEMODIFY", "MOVESP", "MSPHERICAL", "MOVETANG", "RAPIDSTOP", "REGIST",
        "REGIST_SPEED", "REVERSE", "STEP_RATIO",
    ),
    "Input / Output Commands": (
        "AIN", "AIN0..3 / AINBI0..3", "AOUT0..3", "CHANNEL_READ", "CHANNEL_WRITE", "CHR",
        "CLOSE", "CURSOR", "DEFKEY", "ENABLE_OP", "FILE", "FLAG", "FLAGS", "GET", "GET#", "HEX",
        "IN", "INPUT", "INPUTS0 / INPUTS1", "INVERT_IN", "KEY", "LINPUT", "OP", "OPEN", "PRINT",
        "PRINT#", "PSWITCH", "READ_OP", "READPACKET", "SEND", "SETCOM", "TIMER",
    ),
    "Program Loops and Structures": (
        "BASICERROR", "ELSE", "ELSEIF", "ENDIF", "FOR..TO..STEP..NEXT", "GOSUB", "GOTO", "NEXT",
        "ON..GOSUB", "ON..GOTO", "REPEAT..UNTIL", "RETURN", "THEN", "TO", "UNTIL", "WA",
        "WAIT IDLE", "WAIT LOADED", "WAIT UNTIL", "WEND", "WHILE",
    ),
}

#: Words the motion modules simulate (issue 22): the set-up commands of
#: :mod:`~motionsim.sim.trio.card.setup_commands` and the stored start-up / drive parameters of
#: :mod:`~motionsim.sim.trio.card.parameters` — simulated, so not refused (NOT_SIMULATED below).
MOTION_WORDS = frozenset(COMMANDS) | frozenset(p.name for p in STORED) | {"LIMIT_BUFFERED"}
_MOTION_INDEX = MOTION_WORDS & {kw for kws in INDEX.values() for kw in kws}

#: Index entries the simulator runs (with the notes of docs/trio.md).
SIMULATED = _MOTION_INDEX | frozenset({
    "AXIS", "BASE", "CAM", "CAMBOX", "CANCEL", "CONNECT", "DATUM", "DEFPOS", "FORWARD",
    "MHELICAL", "MHELICALSP", "MOVE", "MOVEABS", "MOVEABSSP", "MOVECIRC", "MOVECIRCSP",
    "MOVELINK", "MOVEMODIFY", "MOVESP", "RAPIDSTOP", "REVERSE",
    "HEX", "PRINT", "PRINT#", "AIN", "IN", "OP", "READ_OP",
    "ELSE", "ELSEIF", "ENDIF", "FOR..TO..STEP..NEXT", "GOSUB", "GOTO", "NEXT",
    "REPEAT..UNTIL", "RETURN", "THEN", "TO", "UNTIL", "WA", "WAIT IDLE", "WAIT LOADED",
    "WAIT UNTIL", "WEND", "WHILE", "BASICERROR", "ON..GOSUB", "ON..GOTO",
})

#: Words that start a not-simulated statement or value (index entries split into the words a
#: program writes, plus process commands outside the reachable index).
NOT_SIMULATED = frozenset({
    "ACC", "ADD_DAC", "BACKLASH", "DEC", "DISABLE_GROUP", "MSPHERICAL", "MOVETANG", "REGIST",
    "REGIST_SPEED",
    "AIN0", "AIN1", "AIN2", "AIN3", "AINBI0", "AINBI1", "AINBI2", "AINBI3", "AOUT0",
    "AOUT1", "AOUT2", "AOUT3", "CHANNEL_READ", "CHANNEL_WRITE", "CHR", "CLOSE", "CURSOR",
    "DEFKEY", "ENABLE_OP", "FILE", "FLAG", "FLAGS", "GET", "INPUT", "INPUTS0",
    "INPUTS1", "KEY", "LINPUT", "OPEN", "PSWITCH", "READPACKET", "SEND", "TIMER",
    "RUNTYPE", "TRON", "TROFF", "ENDMOVE_SPEED", "STARTMOVE_SPEED", "FLEXLINK", "CONNPATH",
    "MOVELINK_MODIFY", "JERK",
    # parameters of spec §10.11's tables the simulator does not model: refused by name, so a
    # program does not read them as a local variable that is 0
    "TRANS_DPOS", "TRANSITIONS", "INDEVICE", "LOOKUP", "FRAME", "COMMSERROR", "MSPEEDF",
})


#: Words of the MC4xx / MC6xx language (firmware 2.x, spec §11.1, §11.4) that the earlier
#: generations do not have: on a ``series2`` or ``mc2xx`` model they are the syntax error that
#: generation answers, and they stay ordinary names there; on ``mc4xx`` they are keywords.
MC4_WORDS = frozenset({
    "INCLUDE", "DIM", "AS", "INTEGER", "FLOAT", "STRING", "BOOLEAN", "GLOBAL", "CONSTANT",
    "LEN", "LEFT", "RIGHT", "MID", "INSTR", "VAL", "UCASE", "LCASE", "STR",
    "SELECT_CASE", "CASE", "END_CASE", "EXIT_LOOP", "FUNCTION", "ENDFUNC",
})

#: Models whose language has :data:`MC4_WORDS`, bit access (``v.n``) and string values: the
#: firmware 2.x family (:mod:`motionsim.sim.trio.card.models`, ``mc4xx`` and ``mc6xx``).
MC4_MODELS = frozenset(name for name, m in MODELS.items() if m.mc4)


def index_rows() -> list[tuple[str, str, bool]]:
    """``(section, keyword, simulated)`` for every index entry, in the manual's order."""
    return [(sec, kw, kw in SIMULATED) for sec, kws in INDEX.items() for kw in kws]


__all__ = ["INDEX", "MC4_MODELS", "MC4_WORDS", "NOT_SIMULATED", "SIMULATED", "index_rows"]
