"""A kinematic subroutine compiled once: the lines of ``OPEN FORWARD`` / ``OPEN INVERSE``.

The stored lines (:class:`motionsim.sim.pmac.buffers.program.ProgramLine`) are flattened into
one tuple of steps when the program is first run after its buffer changed; a run then costs a
Python call per statement (the expressions are closures already, :mod:`...language.expressions`).
Assignments (P, Q, I, M; indirect targets) act on the card's variables with the CS's Q bank.
Move, mode and other motion words are ignored in a kinematic buffer ``[INF]`` (the manual's
kinematic programs hold only arithmetic and control flow, TUM p265).
It gives up after :data:`MAX_STEPS` statements (a loop that does not end).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any, Final

from motionsim.sim.pmac.buffers.program import OP_ASSIGN, ProgramLine

#: Statements one run may execute before it is abandoned as a runaway loop ``[INF]``.
MAX_STEPS: Final = 100_000

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
    """One compiled kinematic program."""

    def __init__(self, lines: Sequence[ProgramLine]) -> None:
        steps: list[Step] = []
        for line in lines:
            for op in line.ops:
                if op[0] == OP_ASSIGN:
                    steps.append(_assign(op[1], op[2], op[4]))
        self.steps = tuple(steps)
        self.lines = tuple(lines)

    def run(self, vars_: Any, cs: int) -> set[int]:
        """Execute once; returns the P-variable numbers written.

        Raises:
            KinematicFailure: more than :data:`MAX_STEPS` statements ran.
        """
        written: set[int] = set()
        if len(self.steps) > MAX_STEPS:
            raise KinematicFailure(f"more than {MAX_STEPS} statements in one run")
        for step in self.steps:
            step(vars_, cs, written)
        return written


__all__ = ["MAX_STEPS", "Q_TAG", "KinematicFailure", "Subroutine"]
