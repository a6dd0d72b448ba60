"""A kinematic subroutine compiled once: the lines of ``OPEN FORWARD`` / ``OPEN INVERSE``.

The stored lines, built into instructions with resolved jumps by the motion-program control
flow (:mod:`motionsim.sim.pmac.buffers.flow`: IF / ELSE / ENDIF, WHILE / ENDWHILE, GOTO,
GOSUB / RETURN with N labels), become steps once, when the program is first run after its
buffer changed; a program without control flow is one flat tuple of steps. A run costs a
Python call per statement (the expressions are closures already).
Assignments (P, Q, I, M; indirect targets) act on the card's variables with the CS's Q bank.
Move, mode and other motion words are ignored in a kinematic buffer ``[INF]`` (the manual's
kinematic programs hold only arithmetic and control flow, TUM p265).
It gives up after :data:`MAX_STEPS` statements (a loop that does not end): the card would
trip its watchdog; here a run must stay within what one ~4 ms slice of the event loop holds
(a few thousand Python-level statements), so one host repeating ``&1 PMATCH`` on a looping
forward program cannot hold the service ``[INF]``.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Final

from ..buffers.flow import (
    I_GOSUB,
    I_GOTO,
    I_IF,
    I_JUMP,
    I_LINE,
    I_RETURN,
    I_STOP,
    I_WHILE,
    Code,
)
from ..buffers.program import OP_ASSIGN

#: Statements (each line's assignments, and each IF / WHILE / jump) one run may execute before
#: it is abandoned as a runaway loop ``[INF]``: what a 4 ms slice of the event loop holds.
MAX_STEPS: Final = 5_000

#: A Q-variable n written is recorded as ``Q_TAG + n`` (a P-variable as n).
Q_TAG: Final = 10_000

Step = Callable[[Any, int, set[int]], None]


class KinematicFailure(Exception):
    """A kinematic run produced no valid result (the reason, for the event log)."""


def _assign(kind: str, index: Any, value: Any) -> Step:
    ic = index.const
    vf = value.fn if value.const is None else None
    vc = value.const
    if kind == "P" and ic is not None:
        n = int(ic)

        def step_p(v: Any, cs: int, written: set[int]) -> None:
            v.p[n] = vc if vf is None else vf(v, cs)
            written.add(n)

        return step_p

    def step(v: Any, cs: int, written: set[int]) -> None:
        n = int(ic) if ic is not None else int(index.fn(v, cs))
        v.write(kind, n, vc if vf is None else vf(v, cs), cs)
        if kind == "P":
            written.add(n)
        elif kind == "Q":
            written.add(Q_TAG + n)

    return step


class Subroutine:
    """One compiled kinematic program: its :class:`~motionsim.sim.pmac.buffers.flow.Code`
    (IF / WHILE / GOTO / GOSUB with resolved jumps) turned into steps."""

    def __init__(self, code: Code) -> None:
        prog: list[tuple[int, Any, Any]] = []
        flat = True
        for ins in code.instrs:
            kind = ins[0]
            if kind == I_LINE:
                steps = tuple(_assign(op[1], op[2], op[4]) for op in ins[2].ops
                              if op[0] == OP_ASSIGN)
                prog.append((I_LINE, steps, None))
                continue
            flat = False
            if kind in (I_IF, I_WHILE):
                prog.append((I_IF, ins[2], ins[3]))
            elif kind == I_JUMP:
                prog.append((I_JUMP, ins[2], None))
            elif kind in (I_GOTO, I_GOSUB):
                prog.append((kind, ins[2], None))
            elif kind in (I_RETURN, I_STOP):
                prog.append((I_RETURN, None, None))
            else:  # READ, WAIT, BLOCKSTART/STOP, CALL: no meaning here [INF]
                prog.append((I_LINE, (), None))
        self.prog = tuple(prog)
        self.labels = dict(code.labels)
        #: Without control flow: every step in order (the fast path).
        self.steps = tuple(st for k, a, _b in prog for st in a) if flat else None

    def run(self, vars_: Any, cs: int) -> set[int]:
        """Execute once; returns the P-variable numbers (and ``Q_TAG + n`` of Q-variables)
        written.

        Raises:
            KinematicFailure: more than :data:`MAX_STEPS` instructions ran, or a jump to a
                label that does not exist.
        """
        written: set[int] = set()
        if self.steps is not None:
            if len(self.steps) > MAX_STEPS:
                raise KinematicFailure(f"{len(self.steps)} statements: more than the "
                                       f"{MAX_STEPS} one run may execute")
            for step in self.steps:
                step(vars_, cs, written)
            return written
        prog, labels = self.prog, self.labels
        pc, end, count = 0, len(prog), 0
        stack: list[int] = []
        while pc < end:
            kind, a, b = prog[pc]
            count += max(1, len(a)) if kind == I_LINE else 1
            if count > MAX_STEPS:
                raise KinematicFailure(f"no end after {MAX_STEPS} statements (a loop?)")
            if kind == I_LINE:
                for step in a:
                    step(vars_, cs, written)
                pc += 1
            elif kind == I_IF:
                pc = pc + 1 if a(vars_, cs) else b
            elif kind == I_JUMP:
                pc = a
            elif kind == I_RETURN:
                if not stack:
                    break
                pc = stack.pop()
            else:  # GOTO / GOSUB
                label = int(a(vars_, cs))
                if label not in labels:
                    raise KinematicFailure(f"no label N{label}")
                if kind == I_GOSUB:
                    stack.append(pc + 1)
                pc = labels[label]
        return written


__all__ = ["MAX_STEPS", "Q_TAG", "KinematicFailure", "Subroutine"]
