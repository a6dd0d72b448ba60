"""Trio BASIC as typed values: the parser's output, the compiler's input.

Statements are frozen, slotted dataclasses; expressions are slotted dataclasses, hashable and
compared by value as those are, and never changed once built either (not ``frozen=True``: a
frozen dataclass sets each field through ``object.__setattr__``, three times the cost of
building a plain one, and a 1 000-line program builds thousands of expression nodes — issue
32's compile time). Every statement carries the
1-based ``line`` and ``column`` where it starts in the program text, so a compile error or a
runtime error can name its place the way the controller's ``%[Process n:Line m]`` does.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

# -- expressions -------------------------------------------------------------------------


@dataclass(slots=True, unsafe_hash=True)
class Num:
    """A numeric literal (decimal or ``$`` hex)."""

    value: float


@dataclass(slots=True, unsafe_hash=True)
class Str:
    """A string literal; only PRINT accepts one."""

    value: str


@dataclass(slots=True, unsafe_hash=True)
class Local:
    """A named local variable of the process (reads 0 until written; cleared at RUN)."""

    name: str


@dataclass(slots=True, unsafe_hash=True)
class VrRef:
    """``VR(n)``: a global variable shared by all processes."""

    index: Expr


@dataclass(slots=True, unsafe_hash=True)
class TableRef:
    """``TABLE(n)``: the large global array."""

    index: Expr


@dataclass(slots=True, unsafe_hash=True)
class Param:
    """An axis, process or system parameter: ``NTYPE AXIS(0)``, ``SPEED``, ``PMOVE PROC(2)``.

    ``axis`` is the ``AXIS(n)`` modifier (None = the process' BASE axis); ``proc`` the
    ``PROC(n)`` modifier of a process parameter.
    """

    name: str
    axis: Expr | None = None
    proc: Expr | None = None


@dataclass(slots=True, unsafe_hash=True)
class Unary:
    op: str  # "-" or "NOT"
    operand: Expr


@dataclass(slots=True, unsafe_hash=True)
class Binary:
    op: str  # + - * / ^ MOD = <> < <= > >= AND OR XOR
    left: Expr
    right: Expr


@dataclass(slots=True, unsafe_hash=True)
class Call:
    """A built-in function: ``ABS(x)``, ``SQR(x)``, ``INT(x)`` ..."""

    name: str
    args: tuple[Expr, ...]


@dataclass(slots=True, unsafe_hash=True)
class IoRead:
    """``IN``, ``IN(n)``, ``IN(a, b)``, ``READ_OP(n)``, ``OP(n)``, ``AIN(n)``: the I/O image
    (:mod:`motionsim.sim.trio.card.io`)."""

    name: str
    args: tuple[Expr, ...]


@dataclass(slots=True, unsafe_hash=True)
class Element:
    """``name(i)`` / ``name(i, j)``: an element (from 0) of a local array declared ``DIM
    name(n) AS ...`` / ``DIM name(n, m) AS ...`` — or, when ``name`` is a function of a BASIC
    library, a call of it with ``indices`` as its arguments (MC4)."""

    name: str
    indices: tuple[Expr, ...]


@dataclass(slots=True, unsafe_hash=True)
class Bit:
    """``value.n``: bit ``n`` of the integer part of a value, 0 or 1 (``VR(5).2``,
    ``AXISSTATUS.4``); as an assignment target it sets or clears that bit (MC4)."""

    operand: Expr
    bit: int


Expr = Num | Str | Local | VrRef | TableRef | Param | Unary | Binary | Call | IoRead | Element | Bit

# -- statements --------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Stmt:
    """Base of every statement: where it starts in the text, and the text of its line."""

    line: int
    column: int


@dataclass(frozen=True, slots=True)
class Assign(Stmt):
    """``x = e``, ``VR(n) = e``, ``TABLE(n) = e`` or ``SPEED AXIS(1) = e``."""

    target: Local | VrRef | TableRef | Param | Element | Bit
    value: Expr


@dataclass(frozen=True, slots=True)
class TableWrite(Stmt):
    """``TABLE(n, v1, v2, ...)``: writes consecutive entries from n."""

    start: Expr
    values: tuple[Expr, ...]


@dataclass(frozen=True, slots=True)
class ScopeCmd(Stmt):
    """``SCOPE(enable[, period[, table_start, table_stop, p0 ... p7]])``
    (:mod:`motionsim.sim.trio.run.scope`)."""

    args: tuple[Expr, ...]


@dataclass(frozen=True, slots=True)
class Base(Stmt):
    """``BASE(a, b, ...)``: the axis group the process' motion commands and parameters act on."""

    axes: tuple[Expr, ...]


@dataclass(frozen=True, slots=True)
class MoveCmd(Stmt):
    """A motion command that enters the buffers: MOVE, MOVEABS, MOVECIRC, MHELICAL, FORWARD,
    REVERSE, DATUM. ``axis`` is the ``AXIS(n)`` modifier."""

    kind: str
    args: tuple[Expr, ...]
    axis: Expr | None


@dataclass(frozen=True, slots=True)
class SetupCmd(Stmt):
    """A set-up command of :mod:`motionsim.sim.trio.card.setup_commands` (``ADDAX(2)``,
    ``SETCOM(9600,8,1,2,2)``, ``UNIT_CLEAR``); ``axis`` is the ``AXIS(n)`` modifier."""

    name: str
    args: tuple[Expr, ...]
    axis: Expr | None = None


@dataclass(frozen=True, slots=True)
class BusCall(Stmt):
    """A system / fieldbus function as a statement (``ETHERCAT(0, 0)``,
    ``PROFINET(2, 0, ...)``): :mod:`motionsim.sim.trio.card.fieldbus`."""

    name: str
    args: tuple[Expr, ...]


@dataclass(frozen=True, slots=True)
class OpWrite(Stmt):
    """``OP(n, state)`` (one output) or ``OP(pattern)`` (outputs 8.. from the bits)."""

    args: tuple[Expr, ...]


@dataclass(frozen=True, slots=True)
class Cancel(Stmt):
    """``CANCEL`` / ``CANCEL(1)`` on the base axis (or ``AXIS(n)``)."""

    mode: Expr | None
    axis: Expr | None


@dataclass(frozen=True, slots=True)
class RapidStop(Stmt):
    """``RAPIDSTOP`` / ``RAPIDSTOP(mode)``: cancel the moves of every axis."""

    mode: Expr | None = None


@dataclass(frozen=True, slots=True)
class For(Stmt):
    var: str
    start: Expr
    end: Expr
    step: Expr | None


@dataclass(frozen=True, slots=True)
class Next(Stmt):
    var: str | None


@dataclass(frozen=True, slots=True)
class If(Stmt):
    """One-line ``IF c THEN a [ELSE b]``."""

    cond: Expr
    then: tuple[Stmt, ...]
    orelse: tuple[Stmt, ...]


@dataclass(frozen=True, slots=True)
class IfBlock(Stmt):
    """``IF c THEN`` ending its line: opens a block closed by ``ENDIF``."""

    cond: Expr


@dataclass(frozen=True, slots=True)
class ElseIf(Stmt):
    cond: Expr


@dataclass(frozen=True, slots=True)
class Else(Stmt):
    pass


@dataclass(frozen=True, slots=True)
class EndIf(Stmt):
    pass


@dataclass(frozen=True, slots=True)
class While(Stmt):
    cond: Expr


@dataclass(frozen=True, slots=True)
class Wend(Stmt):
    pass


@dataclass(frozen=True, slots=True)
class Repeat(Stmt):
    pass


@dataclass(frozen=True, slots=True)
class Until(Stmt):
    cond: Expr


@dataclass(frozen=True, slots=True)
class WaitIdle(Stmt):
    """``WAIT IDLE``: until the axis has finished its move and has none buffered."""

    axis: Expr | None


@dataclass(frozen=True, slots=True)
class WaitLoaded(Stmt):
    """``WAIT LOADED``: until the axis has no move waiting in NTYPE."""

    axis: Expr | None


@dataclass(frozen=True, slots=True)
class WaitUntil(Stmt):
    cond: Expr


@dataclass(frozen=True, slots=True)
class Wa(Stmt):
    """``WA(ms)``: wait a number of milliseconds."""

    ms: Expr


@dataclass(frozen=True, slots=True)
class Label(Stmt):
    name: str


@dataclass(frozen=True, slots=True)
class Goto(Stmt):
    label: str


@dataclass(frozen=True, slots=True)
class Gosub(Stmt):
    label: str


@dataclass(frozen=True, slots=True)
class Return(Stmt):
    """``RETURN`` (from a GOSUB) or, in a FUNCTION, ``RETURN value`` (MC4)."""

    value: Expr | None = None


@dataclass(frozen=True, slots=True)
class Hex:
    """``HEX(x)`` as a PRINT item: the integer in two's complement hex."""

    value: Expr


@dataclass(frozen=True, slots=True)
class Print(Stmt):
    """``PRINT`` / ``?``: items with their separators (``";"``, ``","`` or ``""`` for the last)
    and per-item formats ``[d]`` / ``[w,d]`` as ``(width, decimals)`` (``None`` = default);
    ``PRINT #n, ...`` names the output channel (``None``: the process' OUTDEVICE)."""

    items: tuple[tuple[Expr, str], ...]
    formats: tuple[tuple[int, int] | None, ...] = ()
    channel: Expr | None = None


@dataclass(frozen=True, slots=True)
class DefPos(Stmt):
    """``DEFPOS(p1[, p2 ...]) [AXIS(n)]``: the BASE axes' (or axis n's) positions declared, at
    the next servo period."""

    values: tuple[Expr, ...]
    axis: Expr | None = None


@dataclass(frozen=True, slots=True)
class Halt(Stmt):
    """``HALT``: stop every running program."""


@dataclass(frozen=True, slots=True)
class ProcessList(Stmt):
    """``PROCESS``: print the table of running processes."""


@dataclass(frozen=True, slots=True)
class Stop(Stmt):
    """``STOP`` ends this program; ``STOP "name"`` stops the process running that program."""

    program: str | None


@dataclass(frozen=True, slots=True)
class Run(Stmt):
    """``RUN "name" [, process]``."""

    program: str
    process: Expr | None


@dataclass(frozen=True, slots=True)
class Include(Stmt):
    """``INCLUDE "prog"``: the named program's declarations and assignments, made part of
    this program when it is compiled (MC4)."""

    program: str


@dataclass(frozen=True, slots=True)
class Dim(Stmt):
    """``DIM name[(n[, m])] AS INTEGER|FLOAT|STRING[(length)]|BOOLEAN [= value]``: a typed
    local, an array when ``dims`` are given (``size`` elements in all), set to ``init`` when
    declared (MC4)."""

    name: str
    type: str
    size: int | None = None
    length: int | None = None
    dims: tuple[int, ...] = ()
    init: Expr | None = None


@dataclass(frozen=True, slots=True)
class DimList(Stmt):
    """``DIM a, b(4) AS FLOAT``: several names of one type on one line, one :class:`Dim`
    each (MC4)."""

    dims: tuple[Dim, ...]


@dataclass(frozen=True, slots=True)
class Global(Stmt):
    """``GLOBAL "name", vr``: ``name`` stands for ``VR(vr)`` in every program (MC4)."""

    name: str
    index: int


@dataclass(frozen=True, slots=True)
class Constant(Stmt):
    """``CONSTANT "name", value``: ``name`` is a read-only value in every program (MC4)."""

    name: str
    value: float


@dataclass(frozen=True, slots=True)
class SelectCase(Stmt):
    """``SELECT_CASE expr``: opens a block of CASE branches closed by ``END_CASE`` (MC4)."""

    value: Expr


@dataclass(frozen=True, slots=True)
class Case(Stmt):
    """``CASE v1, v2, lo TO hi``: the branch taken when the SELECT_CASE value equals one of
    the values or lies in one of the ranges (``hi`` None: a single value); ``CASE ELSE`` has
    no choices and is taken when no CASE before it was (MC4)."""

    choices: tuple[tuple[Expr, Expr | None], ...]

    @property
    def is_else(self) -> bool:
        return not self.choices


@dataclass(frozen=True, slots=True)
class EndCase(Stmt):
    """``END_CASE``: closes a SELECT_CASE block (MC4)."""


@dataclass(frozen=True, slots=True)
class ExitLoop(Stmt):
    """``EXIT_LOOP``: leave the innermost FOR, WHILE or REPEAT loop (MC4)."""


@dataclass(frozen=True, slots=True)
class Function(Stmt):
    """``FUNCTION name(p1 AS type, ...) [AS type]``: opens a function of a BASIC library,
    closed by ``ENDFUNC`` (MC4). ``params`` are ``(name, type)`` pairs; ``type`` is the
    return value's (None: the function returns no value)."""

    name: str
    params: tuple[tuple[str, str], ...]
    type: str | None


@dataclass(frozen=True, slots=True)
class EndFunc(Stmt):
    """``ENDFUNC``: closes a FUNCTION (MC4)."""


@dataclass(frozen=True, slots=True)
class CallStmt(Stmt):
    """``name(args)`` as a statement: a call of a library function, its value unused (MC4)."""

    call: Element


@dataclass(frozen=True, slots=True)
class OnError(Stmt):
    """``ON BASICERROR GOTO label``: a run-time error of this process continues at ``label``."""

    label: str


@dataclass(frozen=True, slots=True)
class OnBranch(Stmt):
    """``ON expr GOSUB l1, l2, ...`` / ``ON expr GOTO ...``: the integer part of ``expr``
    picks the label, from 1 (TJ2P5-138)."""

    value: Expr
    labels: tuple[str, ...]
    gosub: bool


@dataclass(frozen=True, slots=True)
class Program:
    """A parsed program: its statements in order, the source lines (for messages) and the
    dialect it was parsed in, whose statement table compiles it
    (:class:`motionsim.sim.trio.language.commands.Dialect`)."""

    statements: tuple[Stmt, ...]
    lines: tuple[str, ...]
    dialect: Any
