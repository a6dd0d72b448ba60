"""One coordinate system's run of a fixed motion program: the line source planning reads
(the rotary buffer's interface), following the program's control flow.

Control flow (:mod:`.flow`, spec §12.1) is followed as lines are calculated, so conditions
read the variables at calculation time (TUM p339):

* ``IF`` / ``ELSE`` / ``ENDIF``, ``WHILE`` / ``ENDWHILE``, ``GOTO``, ``GOSUB`` / ``CALL`` /
  ``RETURN`` (``N``/``O`` labels; ``CALL{p}.{l}`` is label ``l``x100,000 of PROG ``p``; the
  program's end is a ``RETURN``, and ``RETURN`` with nothing to return to ends the program),
  ``READ`` (Q101..Q126 and the Q100 bits, TSRM p466), ``STOP`` (halts; ``R`` resumes at the
  next line), ``WAIT``, ``BLOCKSTART``/``BLOCKSTOP``.
* **What ends a calculation pass** besides the lookahead depth: ``WAIT`` (until the next
  RTI, PUM p216) and the **double-jump-back rule** (TUM p341; PUM p215): two backward jumps
  (ENDWHILE, a GOTO back; not GOSUB / CALL / RETURN) met while looking for the next move
  stop the pass; a loop with no move in it thus runs twice per RTI. A move already calculated
  is then not blended into the next: it comes to a stop and calculation resumes once it has
  finished (the planning part, :mod:`motionsim.sim.pmac.lookahead.planning`).
* **Run-time errors** stop the program as calculation falling behind does (``??`` word 2 bit
  22): a jump to a label that is not there, a CALL of a missing PROG, more than
  :data:`MAX_NESTING` nested GOSUB / CALL (PUM p165: 15 on PMAC(1); Turbo depth not found,
  ``[INF]`` the same).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from ...errors import MotionSimError
from ..language.parser import parse_program_line
from .flow import (
    I_BLOCKSTART,
    I_BLOCKSTOP,
    I_CALL,
    I_GOSUB,
    I_GOTO,
    I_IF,
    I_JUMP,
    I_LINE,
    I_READ,
    I_RETURN,
    I_STOP,
    I_WAIT,
    I_WHILE,
    Code,
    build,
)
from .program import ProgramLine, compile_statements

if TYPE_CHECKING:
    from .programs import MotionPrograms

#: Above any line number of any program (see ``ProgramRun.n_loaded``).
N_LINES_MAX = 1 << 30
#: GOSUB / CALL nesting (PUM p165, PMAC(1); [INF] Turbo the same).
MAX_NESTING = 15
#: Instructions followed in one pass without reaching a move: a guard, never reached by a
#: program the card accepts (the double-jump-back rule stops loops first).
_GUARD = 100_000
#: What :meth:`ProgramRun.pending` shows planning for a control-flow instruction.
_FLOW_LINE = ProgramLine("", 0, (), 0)


class _Pending:
    """The rotary buffer's ``pending`` deque, as a program run offers it: true while there is
    something to calculate; ``[0]`` is ``(line number, line)`` at the program counter."""

    __slots__ = ("run",)

    def __init__(self, run: ProgramRun) -> None:
        self.run = run

    def __bool__(self) -> bool:
        return self.run.has_next()

    def __len__(self) -> int:
        return 1 if self.run.has_next() else 0

    def __getitem__(self, i: int) -> tuple[int, ProgramLine]:
        if i != 0:
            raise IndexError(i)
        return self.run.peek()


class ProgramRun:
    """Program ``number`` as coordinate system ``cs``'s line source (the rotary buffer's
    interface: ``pending``, ``take``, ``take_simple``, ``line_calculated``, ``n_loaded``,
    ``calculated``, ``free_calculated``), following its control flow."""

    ends = True  # the program stops at its end (a rotary buffer waits)
    full = False

    def __init__(
        self, cs: int, number: int, programs: MotionPrograms, emit: Callable[..., Any],
        vars_: Any = None, code: Code | None = None,
    ) -> None:
        self.cs = cs
        self.number = number
        self._programs = programs
        self._emit = emit
        self.vars = vars_
        if code is None:  # (given: one rotary line's control flow, number 0)
            code = programs.code(number)
        assert code is not None
        self._code = code
        self._prog = number  # the program whose code runs (a CALL changes it)
        self._pc = 0
        self._stack: list[tuple[Any, ...]] = []
        self._args: tuple[tuple[str, float], ...] = ()
        #: A G/M/T/D code's arguments that no READ took, as text: they run on return
        #: (flow_statements.Call), under the calling line's number; None in a CALL / GOSUB.
        self._unread: tuple[int, tuple[str, ...]] | None = None
        #: The statements of those arguments, taken before the instruction after the call.
        self._resume: tuple[int, ProgramLine] | None = None
        self._jumps = 0
        #: Every line of a fixed program is in memory from the start (of this program or one
        #: it CALLs), so planning always "had its chance" at the next line (the deadline
        #: rule of :mod:`motionsim.sim.pmac.lookahead.execution`).
        self.n_loaded = N_LINES_MAX
        self.calculated: deque[tuple[int, int]] = deque()  # always empty: nothing is freed
        self.pending = _Pending(self)
        #: Why the last :meth:`take` returned None: "suspend" (double jump-back), "wait",
        #: "stop", "end" or "error"; planning reads and clears it.
        self.interrupt: str | None = None
        self.halted = False  # STOP: R resumes at the next line
        self.failed = False  # a run-time error
        self._block = False  # between BLOCKSTART and BLOCKSTOP
        #: The program of the line taken last (a CALLed program's number inside it): the
        #: moves planned from that line carry it, for ``PE``.
        self.taken_prog = number

    # -- where it is ------------------------------------------------------------------------

    @property
    def finished(self) -> bool:
        """At the end with nothing to return to, or stopped by an error: ``R`` starts over."""
        return self.failed or (self._pc >= len(self._code.instrs) and not self._stack)

    def has_next(self) -> bool:
        return not (self.halted or self.finished)

    @property
    def in_block(self) -> bool:
        """Inside a BLOCKSTART ... BLOCKSTOP block with more of it to calculate: a step
        (``S``) goes on calculating (TSRM p182)."""
        if not self._block:
            return False
        instrs = self._code.instrs
        return not (self._pc < len(instrs) and instrs[self._pc][0] == I_BLOCKSTOP)

    def resume(self) -> None:
        """``R`` / ``S`` after ``STOP``: go on at the next line."""
        self.halted = False

    def where(self) -> tuple[int, int]:
        """(program, 1-based line) the program counter points at (past the last line at the
        end)."""
        instrs = self._code.instrs
        if self._pc < len(instrs):
            return self._prog, int(instrs[self._pc][1])
        return self._prog, len(self._programs.programs.get(self._prog, ())) + 1

    def peek(self) -> tuple[int, ProgramLine]:
        instrs = self._code.instrs
        if self._pc >= len(instrs):
            return self.where()[1], _FLOW_LINE
        ins = instrs[self._pc]
        return ins[1], ins[2] if ins[0] == I_LINE else _FLOW_LINE

    # -- taking lines -----------------------------------------------------------------------

    def take_simple(self) -> int:
        """The line at the program counter is a plain constant move: take it."""
        n = self._code.instrs[self._pc][1]
        self._pc += 1
        self._jumps = 0
        self.taken_prog = self._prog
        self.line_calculated(n)
        return n

    def take(self) -> tuple[int, ProgramLine] | None:
        """Follow control flow from the program counter to the next chunk of statements and
        take it; None (with :attr:`interrupt` saying why) when the pass must end first."""
        if self.interrupt is not None:
            self.interrupt = None
        if self.halted or self.finished:
            return None
        for _ in range(_GUARD):
            if self._resume is not None:  # a code's unread arguments, after its return
                item, self._resume = self._resume, None
                self.taken_prog = self._prog
                return item
            instrs = self._code.instrs
            pc = self._pc
            if pc >= len(instrs):
                if not self._return():
                    return self._stop_pass("end")
                continue
            ins = instrs[pc]
            kind = ins[0]
            if kind == I_LINE:
                self._pc = pc + 1
                self.taken_prog = self._prog
                line = ins[2]
                if line.moves:
                    self._jumps = 0
                return ins[1], line
            self._pc = pc + 1
            result = self._step(ins)
            if result is not None:
                return self._stop_pass(result)
        return self._fail(ins[1], "control flow ran on without reaching a move")

    def _stop_pass(self, why: str) -> None:
        self.interrupt = why
        if why in ("suspend", "wait"):
            self._jumps = 0  # the next pass (the next RTI) starts counting again
        return None

    def _fail(self, n: int, reason: str) -> None:
        self.failed = True
        self._emit("program_error", cs=self.cs, prog=self._prog, n=n, reason=reason)
        return self._stop_pass("error")

    def _value(self, expr: Any) -> float:
        return float(expr.const if expr.const is not None else expr.fn(self.vars, self.cs))

    def _jump(self, target: int, n: int) -> str | None:
        """Go to instruction ``target``; a backward jump counts towards the double-jump-back
        rule."""
        back = target < self._pc
        self._pc = target
        if back:
            self._jumps += 1
            if self._jumps >= 2:
                return "suspend"
        return None

    def _label(self, code: Code, label: int, n: int, what: str) -> int | None:
        at = code.labels.get(label)
        if at is None:
            self._fail(n, f"{what}: no label N{label}")
        return at

    def _call(self, code: Code, prog: int, at: int, args: tuple[Any, ...], n: int,
              machine_code: bool = False) -> str | None:
        if len(self._stack) >= MAX_NESTING:
            self._fail(n, f"more than {MAX_NESTING} nested GOSUB/CALL")
            return "error"
        values = tuple((letter, self._value(e)) for letter, e in args)
        self._stack.append((self._code, self._pc, self._prog, self._args, self._unread))
        self._code, self._pc, self._prog, self._args = code, at, prog, values
        texts = tuple(letter + e.text for letter, e in args)
        self._unread = (n, texts) if machine_code and texts else None
        return None

    def _return(self) -> bool:
        """Back to the caller; False in the main program (its end). A G/M/T/D code's
        unread arguments run first (:meth:`_resume_line`)."""
        if not self._stack:
            self._pc = len(self._code.instrs)
            return False
        unread = self._unread
        self._code, self._pc, self._prog, self._args, self._unread = self._stack.pop()
        if unread is not None:
            self._run_unread(*unread)
        return True

    def _run_unread(self, n: int, texts: tuple[str, ...]) -> None:
        """A code's unread arguments are the rest of its line: they run now, as that line
        would (``G90 G01 X10``: G01 is a call too, X10 a move)."""
        text = " ".join(texts)
        try:
            line = compile_statements(text, parse_program_line(text))
        except MotionSimError as e:
            self._fail(n, f"after the code's return: {text!r}: {e.message}")
            return
        if line.flow is None:
            self._resume = (n, line)
            return
        code, problem = build([line])
        if problem is not None:
            self._fail(n, f"after the code's return: {text!r}: {problem}")
            return
        self._call(code, self._prog, 0, (), n)

    def _step(self, ins: list[Any]) -> str | None:
        """Execute one control-flow instruction; a reason to end the pass, or None."""
        kind, n = ins[0], ins[1]
        v, cs = self.vars, self.cs
        if kind in (I_IF, I_WHILE):
            if not ins[2](v, cs):
                return self._jump(ins[3], n)
            return None
        if kind == I_JUMP:
            return self._jump(ins[2], n)
        if kind == I_GOTO:
            at = self._label(self._code, int(self._value(ins[2])), n, "GOTO")
            return "error" if at is None else self._jump(at, n)
        if kind == I_GOSUB:
            at = self._label(self._code, int(self._value(ins[2])), n, "GOSUB")
            return "error" if at is None else self._call(self._code, self._prog, at, ins[3], n)
        if kind == I_CALL:
            target = self._value(ins[2])
            letter = ins[4]
            if letter:
                prog, label = code_target(letter, target)
                what = f"{letter}{target:g} (PROG {prog} N{label})"
            else:
                prog = int(target)
                label = int(round((target - prog) * 100_000))
                what = f"CALL PROG {prog}"
            code = self._programs.code(prog)
            if code is None:
                self._fail(n, f"{what}: there is no PROG {prog}")
                return "error"
            at = self._label(code, label, n, what)
            return "error" if at is None else self._call(code, prog, at, ins[3], n, bool(letter))
        if kind == I_RETURN:
            return None if self._return() else "end"
        if kind == I_READ:
            self._read(ins[2])
            return None
        if kind == I_STOP:
            self.halted = True
            return "stop"
        if kind == I_WAIT:
            return "wait"
        if kind == I_BLOCKSTART:
            self._block = True
        elif kind == I_BLOCKSTOP:
            self._block = False
        return None

    def _read(self, letters: tuple[str, ...]) -> None:
        """``READ``: the calling line's arguments, in order, while their letters are in the
        list: Q(100+N) for letter N (A = 1) and bit N-1 of Q100 (TSRM p466)."""
        bits = 0
        write = self.vars.write
        taken = 0
        for letter, value in self._args:
            if letter not in letters:
                break
            k = ord(letter) - ord("A") + 1
            write("Q", 100 + k, value, self.cs)
            bits |= 1 << (k - 1)
            taken += 1
        write("Q", 100, float(bits), self.cs)
        if self._unread is not None:  # what a code's READ took does not run on return
            n, texts = self._unread
            self._unread = (n, texts[taken:]) if texts[taken:] else None

    def line_calculated(self, n: int) -> None:
        self._emit("line_calculated", cs=self.cs, n=n, prog=self._prog)

    def free_calculated(self) -> None:
        """Program lines stay in memory."""


#: First PROG of each machine-tool code: G 1000, M 1001, T 1002, D 1003 (TSRM p425).
_CODE_PROGS = {"G": 1000, "M": 1001, "T": 1002, "D": 1003}


def code_target(letter: str, value: float) -> tuple[int, int]:
    """(PROG, line label) of a G/M/T/D code: ``CALL 10n{0..3}.({data'}*1000)``, n the
    hundreds digit of the value, ``{data'}`` the rest (TSRM p425: D01 is N1000 of PROG 1003,
    D12 N12000 of PROG 1003, D115 N15000 of PROG 1013)."""
    hundreds = int(value // 100)
    rest = value - 100 * hundreds
    return _CODE_PROGS[letter] + 10 * hundreds, int(round(rest * 1000))


__all__ = ["MAX_NESTING", "N_LINES_MAX", "ProgramRun", "code_target"]
