"""The Turbo PMAC command words as one table: the lexer, the parser's dispatch and the
``not_simulated`` answer are all derived from it.

Each :class:`Keyword` row says how the card spells a command word (the long form, the
abbreviations it accepts, blanks inside the word: ``END IF``, ``END WHILE``; TSRM p23: blanks
are not significant), what it builds (``builds``: the builder function itself, called with
the parser and the keyword's token, returning a statement of
:mod:`motionsim.sim.pmac.language.statements` or of a family module) and whether motionsim
simulates it. How an on-line statement runs is the other half of the command: the
statement's class is one row of the on-line command table
(:mod:`motionsim.sim.pmac.host.commands`). Words a command takes after it (``OPEN PROG``,
``DEFINE GATHER``) are the row's ``objects``, each simulated or not.

Adding a command is one row here (the word and its builder), its statement class, and one
row of the on-line command table with its handler. A row with ``simulated=False`` needs no
builder: the word is recognised and answered ``not_simulated`` naming it
(:mod:`motionsim.sim.pmac.host.not_simulated`), never a parse error.

Spellings are those the manuals and real programs write (spec §12.1: ``ENDW``, ``ENDI``,
``RET``, ``ENA``, ``DIS``, ``CMD``, ``DEF``, ``DEL``, ``ROT``, ``GAT``, ``INV``...); the
minimal abbreviation of every keyword was not found, so none is invented.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Final

from . import (
    axis_definitions,
    card_words,
    flow_words,
    motor_statements,
    online_words,
    plc_idioms,
)
from .object_words import OBJECTS

Builder = Callable[[Any, tuple[str, str, int, int]], Any]


@dataclass(frozen=True)
class Keyword:
    """One command word.

    Attributes:
        name: the long form (what the parser dispatches on).
        spellings: every accepted spelling; a blank means "blanks allowed here".
        builds: the function building the statement (called with the parser, positioned
            after the word, and the word's token), or None (not simulated).
        simulated: whether motionsim models it.
        where: ``"online"``, ``"program"`` (motion program / PLC) or ``"both"``.
        objects: words it takes next -> simulated (``OPEN`` -> ``PROG``: True).
        example: a valid use (documentation and tests of the not-simulated answer).
    """

    name: str
    spellings: tuple[str, ...]
    builds: Builder | None
    simulated: bool = True
    where: str = "both"
    objects: dict[str, bool] = field(default_factory=dict)
    example: str = ""


def _k(name: str, *spellings: str, builds: Builder | None = None, simulated: bool = True,
       where: str = "both", objects: dict[str, bool] | None = None, example: str = "",
       ) -> Keyword:
    return Keyword(name, (name, *spellings), builds, simulated, where, objects or {}, example)


def _ns(name: str, *spellings: str, where: str = "online", example: str = "") -> Keyword:
    """A valid command motionsim does not simulate."""
    return _k(name, *spellings, simulated=False, where=where, example=example or name)


#: The table. Object words (``ROT``, ``PROG``...) are in their own rows below so the lexer
#: knows them; spellings in ``objects`` are the long forms.
TABLE: Final[tuple[Keyword, ...]] = (
    # buffer management (TSRM p260-420)
    _k("DEFINE", "DEF", builds=online_words.define, where="online", objects={
        "ROTARY": True, "GATHER": True, "LOOKAHEAD": True, "CCBUF": False, "COMP": True,
        "TCOMP": False, "BLCOMP": False, "UBUFFER": True}, example="DEFINE CCBUF 10"),
    _k("DELETE", "DEL", builds=online_words.delete, where="online", objects={
        "ROTARY": True, "GATHER": True, "LOOKAHEAD": True, "CCBUF": False, "COMP": True,
        "TCOMP": False, "BLCOMP": False, "PLCC": True, "TEMPS": False, "TRACE": True,
        "ALL": True},
       example="DELETE TEMPS"),
    _k("OPEN", builds=online_words.open_, where="online", objects={
        "ROTARY": True, "PROGRAM": True, "PLC": True, "PLCC": True, "FORWARD": True,
        "INVERSE": True, "BINARY": False, "SERVO": False}, example="OPEN BINARY ROT"),
    _k("CLOSE", builds=online_words.close),
    _k("CLEAR", builds=online_words.clear),
    _k("LIST", builds=online_words.list_, where="online", objects={
        "PLC": True, "PROGRAM": True, "ROTARY": True, "FORWARD": True, "INVERSE": True,
        "GATHER": True, "LDS": False, "LINK": False, "TCOMP": False, "COMP": False,
        "BLCOMP": False, "CCBUF": False, "LOOKAHEAD": False}, example="LIST LDS"),
    _k("MFLUSH", builds=online_words.mflush, where="online"),
    # data gathering (TSRM p170-171, p307, p315; sim.pmac.tasks.gather)
    _k("GATHER", "GAT", builds=online_words.gather, where="online",
       objects={"TRIGGER": True}, example="GATHER TRIGGER"),
    _k("ENDGATHER", "ENDG", "END GATHER", "END GAT", "ENDGAT", builds=online_words.endgather,
       where="online"),
    _k("SAVE", builds=online_words.save, where="online"),
    _k("ENABLE", "ENA", builds=online_words.enable, objects={"PLC": True, "PLCC": True}),
    _k("DISABLE", "DIS", builds=online_words.enable, objects={"PLC": True, "PLCC": True}),
    # reports
    _k("VERSION", "VER", builds=online_words.query, where="online"),
    _k("CID", builds=online_words.query, where="online"),
    _k("CPU", builds=online_words.query, where="online"),
    _k("VID", builds=online_words.query, where="online"),
    _k("TYPE", builds=online_words.query, where="online"),
    _k("SIZE", builds=online_words.query, where="online"),
    _k("PR", builds=online_words.query, where="online"),
    # motors
    _k("HOME", "HM", builds=motor_statements.home_word),
    _k("HOMEZ", "HMZ", builds=motor_statements.home_word),
    # motion-program statements (TSRM p425-480)
    _k("LINEAR", "LIN", builds=online_words.move_mode, where="program"),
    _k("RAPID", "RPD", builds=online_words.move_mode, where="program"),
    _k("CIRCLE", "CIR", builds=online_words.circle, where="program"),
    _k("SPLINE", builds=online_words.spline, where="program"),
    _k("PVT", builds=online_words.pvt, where="program"),
    _k("PSET", builds=online_words.pset, where="program"),
    _k("INC", builds=online_words.axis_mode, where="program"),
    _k("ABS", builds=online_words.axis_mode, where="program"),
    _k("TA", builds=online_words.modal, where="program"),
    _k("TS", builds=online_words.modal, where="program"),
    _k("TM", builds=online_words.modal, where="program"),
    _k("DWELL", "DWE", builds=online_words.dwell, where="program"),
    _k("DELAY", "DLY", builds=online_words.delay, where="program"),
    _k("SEND", "SENDS", "SENDP", "SENDR", "SENDA", builds=plc_idioms.message_word,
       where="program"),
    _k("COMMAND", "CMD", "COMMANDS", "CMDS", "COMMANDP", "CMDP", "COMMANDR", "CMDR",
       "COMMANDA", "CMDA", builds=plc_idioms.message_word, where="program"),
    _k("ADDRESS", "ADR", builds=plc_idioms.address_word, where="program"),
    # axis definitions (spec §12.5)
    _k("FRAX", builds=axis_definitions.frax_word, where="program"),
    # control flow (spec §12.1): flow_words
    _k("IF", builds=flow_words.if_, where="program"),
    _k("ELSE", builds=flow_words.else_, where="program"),
    _k("ENDIF", "END IF", "ENDI", builds=flow_words.endif, where="program"),
    _k("WHILE", builds=flow_words.while_, where="program"),
    _k("ENDWHILE", "END WHILE", "ENDW", builds=flow_words.endwhile, where="program"),
    _k("AND", builds=flow_words.cond_line, where="program"),
    _k("OR", builds=flow_words.cond_line, where="program"),
    _k("GOTO", builds=flow_words.goto, where="program"),
    _k("GOSUB", builds=flow_words.gosub, where="program"),
    _k("CALL", builds=flow_words.call, where="program"),
    _k("RETURN", "RET", builds=flow_words.return_, where="program"),
    _k("READ", builds=flow_words.read, where="program"),
    _k("STOP", builds=flow_words.stop, where="program"),
    _k("WAIT", builds=flow_words.wait, where="program"),
    _k("BLOCKSTART", builds=flow_words.block_start, where="program"),
    _k("BLOCKSTOP", builds=flow_words.block_stop, where="program"),
    # valid, not simulated (TSRM on-line and program command lists)
    # card memory and kinematics (issue 24): card_words
    _k("UNDEFINE", "UNDEF", builds=card_words.undefine, where="online"),
    _k("PMATCH", builds=card_words.pmatch, where="online"),
    _ns("PASSWORD", example="PASSWORD=SECRET"),
    _ns("CHECKSUM"),
    _ns("EAVERSION"),
    _ns("DATE"),
    _ns("TIME"),
    _ns("IDNUMBER"),
    _ns("IDC"),
    _ns("SID"),
    _ns("UPDATE"),
    _ns("RESET"),
    _ns("MOVETIME", example="&1MOVETIME"),
    _ns("HOLD", example="#1HOLD"),
    _ns("PRELUDE", where="program", example="PRELUDE1 CALL10"),
    # cutter radius compensation (TSRM program commands CC0, CC1, CC2, CC3, CCR; TUM "Cutter
    # Radius Compensation"): valid, not simulated
    _ns("CC0", where="program", example="CC0"),
    _ns("CC1", where="program", example="CC1"),
    _ns("CC2", where="program", example="CC2"),
    _ns("CC3", where="program", example="CC3"),
    _ns("CCR", where="program", example="CCR0.25"),
    _ns("TSELECT", where="program", example="TSELECT1"),
    _ns("NORMAL", where="program", example="NORMAL K-1"),
    _ns("DISPLAY", where="program", example='DISPLAY "HELLO"'),
    _ns("NOFRAX", where="program"),
    _ns("FRAX2", where="program", example="FRAX2(X,Y)"),
    _ns("NOFRAX2", where="program"),
    _ns("TINIT", where="program"),
    _ns("ADIS", where="program", example="ADIS10"),
    _ns("IDIS", where="program", example="IDIS10"),
    _ns("AROT", where="program", example="AROT10"),
    _ns("IROT", where="program", example="IROT10"),
    _ns("LOCK", example="LOCK4,P1"),
    _ns("UNLOCK", example="UNLOCK4"),
    _ns("SETPHASE", example="SETPHASE1"),
)

#: Every accepted spelling of a command word (blanks removed) -> its row.
BY_SPELLING: Final[dict[str, Keyword]] = {
    s.replace(" ", ""): k for k in TABLE for s in k.spellings
}
#: Words of the condition syntax (not statements).
CONDITION_WORDS: Final = ("AND", "OR")


def lexer_words(extra: tuple[str, ...] = ()) -> list[str]:
    """Every word the lexer reads whole: the table's spellings and objects, the condition
    words and ``extra``."""
    words = {s for k in TABLE for s in k.spellings} | set(OBJECTS) | set(CONDITION_WORDS)
    return sorted(words | set(extra))


def lexer_pattern(words: list[str]) -> str:
    """One regular expression matching the longest of ``words`` at a position, built as a
    trie (``A(?:BS|TAN2?|...)``) so the engine does not try every word in turn; a blank in
    a spelling matches any run of blanks (``END\\s*IF``)."""
    trie: dict[str, Any] = {}
    for w in words:
        node = trie
        for ch in w.upper():
            node = node.setdefault(ch, {})
        node[""] = {}

    def depth(node: dict[str, Any]) -> int:
        return max((1 + depth(child) for ch, child in node.items() if ch), default=0)

    def emit(node: dict[str, Any]) -> str:
        children = sorted((ch for ch in node if ch), key=lambda ch: -depth(node[ch]))
        alts = [(r"\s*" if ch == " " else re.escape(ch)) + emit(node[ch]) for ch in children]
        if not alts:
            return ""
        if len(alts) == 1 and "" not in node:
            return alts[0]
        return "(?:" + "|".join(alts) + ")" + ("?" if "" in node else "")

    return emit(trie)


def lookup(word: str) -> Keyword | None:
    """The row of a word token (``END IF`` with any blanks, ``ENDI``, ``ENDIF``)."""
    k = BY_SPELLING.get(word)
    if k is None and (" " in word or "\t" in word):
        k = BY_SPELLING.get("".join(word.split()))
    return k


def not_simulated() -> list[tuple[str, str]]:
    """(pattern, name) of every valid command word or command + object that is not
    simulated, for :mod:`motionsim.sim.pmac.host.not_simulated`."""
    out: list[tuple[str, str]] = []
    for k in sorted(TABLE, key=lambda k: -max(map(len, k.spellings))):  # FRAX2 before FRAX
        spell = "|".join(r"\s*".join(s.split(" ")) for s in k.spellings)
        if not k.simulated:
            out.append((rf"(?:{spell})(?![A-Z])", k.name))
        for obj, simulated in k.objects.items():
            if simulated:
                continue
            objs = "|".join(s for s, name in OBJECTS.items() if name == obj) or obj
            out.append((rf"(?:{spell})\s*(?:{objs})(?![A-Z])", f"{k.name} {obj}"))
    return out


def examples() -> list[tuple[str, str]]:
    """(example command, name) for every not-simulated row and object (for tests/docs)."""
    out: list[tuple[str, str]] = []
    for k in TABLE:
        if not k.simulated:
            out.append((k.example, k.name))
        for obj, simulated in k.objects.items():
            if not simulated:
                out.append((f"{k.name} {obj}", f"{k.name} {obj}"))
    return out


__all__ = [
    "BY_SPELLING", "CONDITION_WORDS", "OBJECTS", "TABLE", "Builder", "Keyword", "examples",
    "lexer_pattern",
    "lexer_words",
    "lookup", "not_simulated",
]  # fmt: skip
