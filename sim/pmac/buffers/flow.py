"""A fixed motion program's lines turned into instructions with resolved jumps (spec §12.1).

The card compiles a program line when it is entered, so its structure is checked then
(:class:`Structure`, fed one line at a time by :mod:`.programs`):

* ``ELSE`` with no open ``IF``, ``ENDIF`` with no open ``IF``/``ELSE``, ``ENDWHILE`` with no
  open ``WHILE`` is a **program structural error**, ERR009 (TSRM I6 error table; spec §2.2)
  with the column of the word; the line is refused and nothing is stored;
* an ``IF`` / ``WHILE`` block still open at ``CLOSE`` is ERR009 as well ``[INF]``: entry
  ends all the same (the buffer closes) and running the program answers ERR016, "running
  improperly structured program" ``[INF]``.

One-line forms (PSRM p313, p357): ``IF (c) {statements}`` ends with its line and may be
followed by an ``ELSE`` at the start of the next line — ``ELSE {statements}`` one line, or a
block ``ELSE`` ... ``ENDIF``; ``WHILE (c) {statements}`` loops over its own line.

An instruction is a list whose first element is its kind (``I_*``) and second the 1-based
program line it comes from. The statements of a line between two control-flow words form
one :class:`~motionsim.sim.pmac.buffers.program.ProgramLine` chunk (``I_LINE``) planned like
any line; a line without control flow is its own chunk.

**One structure for every context** (issue 31 item 1). PLCs (:mod:`..tasks.plc`), fixed and
rotary motion programs and kinematic programs are all built here; a :class:`Context` says
the two ways they differ (PUM p162):

* *one-line forms* are motion-program forms ("Single-Line Condition Actions"). In a PLC the
  statements after ``IF (c)``, ``WHILE (c)`` or ``ELSE`` belong to a block that an
  ``ENDIF`` / ``ENDWHILE`` must close (PSRM p313: the card "puts the statements on the next
  program line and expects an ENDIF");
* *multi-line conditions* (``AND (c)`` / ``OR (c)`` starting a line, extending the condition
  of the ``IF`` / ``WHILE`` that ended the line just above) are for PLCs only.

A PLC has no moves: each of its statements is an instruction of its own, made by the
``leaf`` the PLC gives (:meth:`Structure.feed_statements`). Who steps the instructions keeps
its own stop rule: a PLC scan ends at the backward jump of an ``ENDWHILE`` (the next scan
resumes at the ``WHILE``), the lookahead plans on through it.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

from ...errors import ParseError
from ..language import flow_statements as fl
from ..language import statements as st
from ..language.conditions import any_of_all
from .program import ProgramLine, compile_statements

I_LINE = 0  # (I_LINE, n, ProgramLine)
I_IF = 1  # (I_IF, n, cond, target if false)
I_WHILE = 2  # (I_WHILE, n, cond, target if false)
I_JUMP = 3  # (I_JUMP, n, target, backward)
I_GOTO = 4  # (I_GOTO, n, label expr)
I_GOSUB = 5  # (I_GOSUB, n, label expr, args)
I_CALL = 6  # (I_CALL, n, prog.label expr, args, code letter or "")
I_RETURN = 7  # (I_RETURN, n)
I_READ = 8  # (I_READ, n, letters)
I_STOP = 9  # (I_STOP, n)
I_WAIT = 10  # (I_WAIT, n)
I_BLOCKSTART = 11  # (I_BLOCKSTART, n)
I_BLOCKSTOP = 12  # (I_BLOCKSTOP, n)

STRUCTURAL = "ERR009"


def _error(message: str, text: str, column: int) -> ParseError:
    return ParseError(f"{message} (column {column})", column=column, text=text,
                      pmac_error=STRUCTURAL)


@dataclass(frozen=True, slots=True)
class Context:
    """What a context's lines may hold of the shared control flow (PUM p162)."""

    name: str
    #: ``IF (c) {statements}``, ``ELSE {statements}``, ``WHILE (c) {action}`` end with their line.
    one_line_forms: bool
    #: ``AND (c)`` / ``OR (c)`` lines extend the condition of the IF / WHILE just above.
    condition_lines: bool


#: Fixed and rotary motion programs and kinematic programs.
PROGRAM = Context("program", one_line_forms=True, condition_lines=False)
#: PLC programs, interpreted and compiled.
PLC = Context("PLC", one_line_forms=False, condition_lines=True)

#: How a context without moves turns one statement of line ``n`` into its instruction.
Leaf = Callable[[Any, int], list[Any]]


@dataclass
class _Open:
    """An IF / ELSE / WHILE not yet closed."""

    kind: str  # "IF", "ELSE", "WHILE"
    at: int  # its instruction (the IF / WHILE, or the ELSE's jump)
    n: int  # its program line
    inline: bool
    column: int
    awaiting: bool = False  # a one-line IF whose line has ended: an ELSE may follow


@dataclass
class Code:
    """A program's instructions and its labels (``N``/``O`` number -> instruction index;
    ``N0`` is the top, TSRM p416)."""

    instrs: list[list[Any]] = field(default_factory=list)
    labels: dict[int, int] = field(default_factory=lambda: {0: 0})


class Structure:
    """Builds a program's :class:`Code` line by line, refusing structural errors. A ``dry``
    structure only checks (entry): it keeps the open blocks and an instruction count."""

    def __init__(self, dry: bool = False, context: Context = PROGRAM,
                 leaf: Leaf | None = None) -> None:
        self.code = Code()
        self.dry = dry
        self.context = context
        self.leaf = leaf
        self._open: list[_Open] = []
        self._n = 0
        self._count = 0
        #: The IF / WHILE instruction an ``AND`` / ``OR`` line may extend, and the OR-groups
        #: of AND-ed conditions it holds so far (PLC multi-line conditions).
        self._cond_at: int | None = None
        self._groups: list[list[Any]] = []

    def copy(self) -> Structure:
        """A dry copy to try a line on (entry: a refused line leaves this one unchanged)."""
        c = Structure(dry=True, context=self.context, leaf=self.leaf)
        c._open = [_Open(o.kind, o.at, o.n, o.inline, o.column, o.awaiting) for o in self._open]
        c._n, c._count = self._n, self._count
        c._cond_at, c._groups = self._cond_at, [list(g) for g in self._groups]
        return c

    def unclosed(self) -> str | None:
        """The innermost block left open, for the ERR009 at CLOSE, or None."""
        for o in reversed(self._open):
            if not o.awaiting:
                return f"{o.kind} of line {o.n} (column {o.column}) is not closed"
        return None

    def feed(self, line: ProgramLine) -> None:
        """Add the next program line.

        Raises:
            ParseError: ERR009 with the column of the word that breaks the structure.
        """
        self._feed(line)

    def feed_statements(self, text: str, stmts: Sequence[tuple[Any, int]]) -> None:
        """Add the next line of a context without moves (a PLC): its statements with their
        1-based columns; each statement that is not a control-flow word becomes one
        instruction through ``leaf``.

        Raises:
            ParseError: ERR009 with the column of the word that breaks the structure; ERR003
            for an ``AND`` / ``OR`` line with no IF / WHILE line just above it.
        """
        assert self.leaf is not None, "a context without moves gives its leaf"
        self._n += 1
        n = self._n
        for s, col in stmts:
            t = type(s)
            if t is fl.CondLine:
                self._extend(s, col, text)
                continue
            at = self._here()
            if isinstance(s, fl.FLOW_TYPES):
                self._flow(s, n, text, getattr(s, "inline", False) and self.context.one_line_forms)
            else:
                self._emit(self.leaf(s, n))
            if t is fl.If or t is fl.While:  # an AND / OR line may extend it if it ends the line
                self._cond_at = None if s.inline else at
                self._groups = [[s.cond]]
            else:
                self._cond_at = None
        if self.context.one_line_forms:
            self._line_end(n)

    def _extend(self, s: fl.CondLine, col: int, text: str) -> None:
        """``AND (c)`` / ``OR (c)`` line: the condition of the IF / WHILE above becomes
        ``(above) AND c`` / ``(above) OR c`` (AND binds tighter, PUM p162)."""
        if not self.context.condition_lines or self._cond_at is None:
            where = ("just above" if self.context.condition_lines
                     else f"(multi-line conditions are for PLCs; not in a {self.context.name})")
            raise ParseError(f"{s.op} line without an IF or WHILE {where}", column=col,
                             text=text, pmac_error="ERR003")
        if s.op == "AND":
            self._groups[-1].append(s.cond)
        else:
            self._groups.append([s.cond])
        if not self.dry:
            self.code.instrs[self._cond_at][2] = any_of_all(self._groups)

    def finish(self) -> Code:
        """The code with every one-line IF resolved at the end of the program."""
        self._resolve_awaiting(None)
        return self.code

    # -- building ---------------------------------------------------------------------------

    def _emit(self, instr: list[Any]) -> int:
        if not self.dry:
            self.code.instrs.append(instr)
        self._count += 1
        return self._count - 1

    def _here(self) -> int:
        return self._count

    def _patch(self, at: int, slot: int, value: int) -> None:
        if not self.dry:
            self.code.instrs[at][slot] = value

    def _resolve_awaiting(self, first: Any) -> None:
        """At a line start: a one-line IF of the line before is closed unless the line
        starts with ELSE."""
        while self._open and self._open[-1].awaiting and not isinstance(first, fl.Else):
            o = self._open.pop()
            self._patch(o.at, 3, self._here())

    def _feed(self, line: ProgramLine) -> None:
        self._n += 1
        n = self._n
        stmts = line.flow
        if stmts is None:
            self._resolve_awaiting(None)
            self._emit([I_LINE, n, line])
            return
        self._resolve_awaiting(stmts[0] if stmts else None)
        seg: list[Any] = []

        def flush() -> None:
            if seg:
                chunk = line if self.dry else compile_statements(line.text, list(seg))
                self._emit([I_LINE, n, chunk])
                seg.clear()

        for s in stmts:
            if isinstance(s, st.Label):
                flush()
                if not self.dry:
                    self.code.labels.setdefault(s.n, self._here())
            elif isinstance(s, fl.FLOW_TYPES):
                flush()
                self._flow(s, n, line.text, getattr(s, "inline", False))
            else:
                seg.append(s)
        flush()
        self._line_end(n)

    def _flow(self, s: Any, n: int, text: str, inline: bool) -> None:
        """One control-flow word; ``inline``: a one-line form (a program context only)."""
        opened = self._open
        t = type(s)
        if t is fl.If:
            at = self._emit([I_IF, n, s.cond, None])
            opened.append(_Open("IF", at, n, inline, s.column))
        elif t is fl.While:
            at = self._emit([I_WHILE, n, s.cond, None])
            opened.append(_Open("WHILE", at, n, inline, s.column))
        elif t is fl.Else:
            top = opened[-1] if opened else None
            if top is None or top.kind != "IF":
                raise _error("ELSE without an open IF", text, s.column)
            jump = self._emit([I_JUMP, n, None, False])
            self._patch(top.at, 3, self._here())
            opened[-1] = _Open("ELSE", jump, n, inline, s.column)
        elif t is fl.EndIf:
            top = opened[-1] if opened else None
            if top is None or top.kind not in ("IF", "ELSE") or top.inline:
                raise _error("ENDIF without an open IF", text, s.column)
            opened.pop()
            self._patch(top.at, 2 if top.kind == "ELSE" else 3, self._here())
        elif t is fl.EndWhile:
            top = opened[-1] if opened else None
            if top is None or top.kind != "WHILE" or top.inline:
                raise _error("ENDWHILE without an open WHILE", text, s.column)
            opened.pop()
            self._emit([I_JUMP, n, top.at, True])
            self._patch(top.at, 3, self._here())
        elif t is fl.Goto:
            self._emit([I_GOTO, n, s.target])
        elif t is fl.Gosub:
            self._emit([I_GOSUB, n, s.target, s.args])
        elif t is fl.Call:
            self._emit([I_CALL, n, s.target, s.args, s.code])
        elif t is fl.Return:
            self._emit([I_RETURN, n])
        elif t is fl.Read:
            self._emit([I_READ, n, s.letters])
        elif t is fl.Stop:
            self._emit([I_STOP, n])
        elif t is fl.Wait:
            self._emit([I_WAIT, n])
        elif t is fl.BlockStart:
            self._emit([I_BLOCKSTART, n])
        elif t is fl.BlockStop:
            self._emit([I_BLOCKSTOP, n])

    def _line_end(self, n: int) -> None:
        """Close the one-line forms opened on line ``n``."""
        opened = self._open
        while opened and opened[-1].n == n and opened[-1].inline and not opened[-1].awaiting:
            o = opened[-1]
            if o.kind == "WHILE":
                opened.pop()
                self._emit([I_JUMP, n, o.at, True])
                self._patch(o.at, 3, self._here())
            elif o.kind == "ELSE":
                opened.pop()
                self._patch(o.at, 2, self._here())
            else:  # a one-line IF: an ELSE may start the next line
                o.awaiting = True
                break


def build(lines: list[ProgramLine]) -> tuple[Code, str | None]:
    """The code of a whole program and what is left open (None when well structured)."""
    s = Structure()
    for line in lines:
        s.feed(line)
    problem = s.unclosed()
    return s.finish(), problem


__all__ = [
    "I_BLOCKSTART", "I_BLOCKSTOP", "I_CALL", "I_GOSUB", "I_GOTO", "I_IF", "I_JUMP", "I_LINE",
    "I_READ", "I_RETURN", "I_STOP", "I_WAIT", "I_WHILE", "PLC", "PROGRAM", "STRUCTURAL", "Code",
    "Context", "Leaf", "Structure", "build",
]  # fmt: skip
