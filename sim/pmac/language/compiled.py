"""The compiled form of a motion-program line: operation codes and :class:`ProgramLine`.

What the compiler (:mod:`motionsim.sim.pmac.buffers.program`, which also counts the line's
words) and the streamed-line fast path (:mod:`.fast_line`) both build, and what planning
(:mod:`motionsim.sim.pmac.lookahead`) and the program run step through. Here, below both, so
the fast path needs nothing above the language.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

# Operation codes (first element of each op tuple).
OP_ASSIGN = 0  # (OP_ASSIGN, kind, index_expr, op, value_expr)
OP_MODAL = 1  # (OP_MODAL, name, expr)
OP_MODE = 2  # (OP_MODE, mode)
OP_AXISMODE = 3  # (OP_AXISMODE, incremental, axes|None)
OP_MOVE = 4  # (OP_MOVE, ((axis, expr), ...), ((vector, expr), ...), ((axis, vel_expr), ...))
OP_DWELL = 5  # (OP_DWELL, expr)
OP_DELAY = 6  # (OP_DELAY, expr)
OP_PSET = 7  # (OP_PSET, ((axis, expr), ...))
OP_FRAX = 8  # (OP_FRAX, axes)
OP_SEND = 9  # (OP_SEND, port letter, text)
OP_HOME = 10  # (OP_HOME, motors, zero)


@dataclass(eq=True, unsafe_hash=True, slots=True)
class ProgramLine:
    """One line of a motion program, parsed and compiled once.

    Immutable once built (lines are cached by text and shared); not a frozen dataclass, for
    the reason :class:`~motionsim.sim.pmac.language.expressions.Expr` is not (one per streamed
    line). Equality and hash are the frozen class's."""

    text: str
    words: int
    ops: tuple[tuple[Any, ...], ...]
    moves: int  # number of motion operations (moves, dwells, delays)
    #: ``((axis, value), ...)`` when the line is nothing but one move with constant axis
    #: values (the common streamed line): planning takes a short cut for it.
    simple: tuple[tuple[str, float], ...] | None = None
    #: ``((axis, position, velocity), ...)`` when the line is one move with constant axis
    #: values and constant (or no) PVT velocities: the PVT planning short cut.
    simple_pvt: tuple[tuple[str, float, float], ...] | None = None
    #: The line's statements when it holds control flow or a label (``N10``, ``IF (...)``,
    #: ``GOSUB20``): :mod:`.flow` splits it at them; None for a plain line.
    flow: tuple[Any, ...] | None = None

    def __init__(
        self, text: str, words: int, ops: tuple[tuple[Any, ...], ...], moves: int,
        simple: tuple[tuple[str, float], ...] | None = None,
        simple_pvt: tuple[tuple[str, float, float], ...] | None = None,
        flow: tuple[Any, ...] | None = None,
    ) -> None:
        self.text = text
        self.words = words
        self.ops = ops
        self.moves = moves
        self.simple = simple
        self.simple_pvt = simple_pvt
        self.flow = flow


__all__ = [
    "OP_ASSIGN", "OP_AXISMODE", "OP_DELAY", "OP_DWELL", "OP_FRAX", "OP_HOME", "OP_MODAL", "OP_MODE",
    "OP_MOVE", "OP_PSET", "OP_SEND", "ProgramLine",
]  # fmt: skip
