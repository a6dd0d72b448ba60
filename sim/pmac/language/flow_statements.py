"""Control-flow statements of a Turbo PMAC motion program (spec §12.1; TSRM p416, p466;
PSRM p301, p313, p357; PUM p165; TUM p252, p330, p341).

They are stored in fixed ``PROG`` buffers like any program statement and turned into jumps
when a program is run (:mod:`motionsim.sim.pmac.buffers.flow`). ``column`` is where the
statement starts in the line as sent (1-based), for the ERR009 answer of a structural
error. The same statements make up PLC programs (:mod:`motionsim.sim.pmac.tasks.plc`
compiles them with the PLC's rules). A condition is read by the parser
(:meth:`motionsim.sim.pmac.language.parser._Parser.condition`): a function of the variables
and the coordinate system.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from .expressions import Expr

Cond = Callable[[Any, int], bool]


@dataclass(frozen=True, slots=True)
class If:
    """``IF ({condition})``; ``inline``: statements follow on the same line (the one-line
    form, no ``ENDIF``; PSRM p313)."""

    cond: Cond
    text: str
    inline: bool
    column: int


@dataclass(frozen=True, slots=True)
class Else:
    """``ELSE``; ``inline``: ``ELSE {statements}`` on one line, which also ends the IF."""

    inline: bool
    column: int


@dataclass(frozen=True, slots=True)
class EndIf:
    """``ENDIF`` (``ENDI``, ``END IF``)."""

    column: int


@dataclass(frozen=True, slots=True)
class While:
    """``WHILE ({condition})``; ``inline``: ``WHILE (c) {action}`` on one line (motion
    programs only, PSRM p357), the loop being that line."""

    cond: Cond
    text: str
    inline: bool
    column: int


@dataclass(frozen=True, slots=True)
class EndWhile:
    """``ENDWHILE`` (``ENDW``, ``END WHILE``): jump back to the WHILE."""

    column: int


@dataclass(frozen=True, slots=True)
class CondLine:
    """``AND ({condition})`` / ``OR ({condition})`` starting a line: it extends the condition
    of the ``IF`` / ``WHILE`` line just above (PLC programs only, PUM p162 "Multiple-Line
    Conditions"; TUM p253). ``op`` is ``"AND"`` or ``"OR"``."""

    op: str
    cond: Cond
    text: str
    column: int


@dataclass(frozen=True, slots=True)
class Goto:
    """``GOTO{data}``: jump to label ``N{data}`` of the same program, no return."""

    target: Expr
    column: int


@dataclass(frozen=True, slots=True)
class Gosub:
    """``GOSUB{data}[{letter}{data}...]``: jump to label ``N{data}`` with return; the letter
    and value pairs after it are the arguments a ``READ`` picks up."""

    target: Expr
    args: tuple[tuple[str, Expr], ...]
    column: int


@dataclass(frozen=True, slots=True)
class Call:
    """``CALL{prog}[.{label}][{letter}{data}...]``: jump to PROG ``prog`` (label = fraction x
    100,000; ``CALL35.1`` is N10000 of PROG 35) with return (TSRM p416).

    ``code`` ``"G"`` / ``"M"`` / ``"T"`` / ``"D"``: a machine-tool code, ``target`` its
    value: ``G{data}`` is ``CALL 10n0.({data'}*1000)``, n the hundreds digit of the value and
    ``{data'}`` the rest (``G01`` is N1000 of PROG 1000, ``G115`` N15000 of PROG 1010); M-,
    T-, D-codes the same into PROG 10n1, 10n2, 10n3 (TSRM p425 D{data}; TUM p328-330). The
    letters after the code are its arguments (``READ``); those the subroutine does not read
    run when it returns (``G01 X10 Y20``: LINEAR, then the move; TUM p330 "N01000 LINEAR
    RETURN") ``[INF]`` for the unread ones."""

    target: Expr
    args: tuple[tuple[str, Expr], ...]
    column: int
    code: str = ""


@dataclass(frozen=True, slots=True)
class Return:
    """``RETURN`` (``RET``): back to the line after the GOSUB / CALL; in the main program
    the end of the program (TUM p330)."""

    column: int


@dataclass(frozen=True, slots=True)
class Read:
    """``READ({letter}[,{letter}...])``: the calling line's values after those letters into
    Q(100+N) (A = Q101 ... Z = Q126), bit N-1 of Q100 for each one read (TSRM p466)."""

    letters: tuple[str, ...]
    column: int


@dataclass(frozen=True, slots=True)
class Stop:
    """``STOP``: halt the program here; ``R`` / ``S`` resumes at the next line."""

    column: int


@dataclass(frozen=True, slots=True)
class Wait:
    """``WAIT``: suspend calculation until the next RTI (PUM p216)."""

    column: int


@dataclass(frozen=True, slots=True)
class BlockStart:
    """``BLOCKSTART``: a step (``S``) runs on to the ``BLOCKSTOP`` (TSRM p182)."""

    column: int


@dataclass(frozen=True, slots=True)
class BlockStop:
    """``BLOCKSTOP``: the end of a block a step runs through."""

    column: int


FlowStatement = (
    If | Else | EndIf | While | EndWhile | Goto | Gosub | Call | Return | Read | Stop | Wait
    | BlockStart | BlockStop
)
FLOW_TYPES = (
    If, Else, EndIf, While, EndWhile, Goto, Gosub, Call, Return, Read, Stop, Wait, BlockStart,
    BlockStop,
)

__all__ = [
    "FLOW_TYPES", "BlockStart", "BlockStop", "Call", "CondLine", "Else", "EndIf", "EndWhile",
    "FlowStatement", "Gosub", "Goto", "If", "Read", "Return", "Stop", "Wait", "While",
]  # fmt: skip
