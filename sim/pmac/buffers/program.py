"""A stored program line: its statements compiled to operations, and its size in words.

Words per line (seed 000: "each value in a program (e.g. X1250) takes one word"): we count
**one word per command word**, with or without a value, and one more for a PVT axis word's
velocity (``X10:5`` holds two values, ``[INF]``: no PVT figure is published) — ``X1250`` is
one word, ``X10 Y20`` two, ``P1=P2+1`` one, ``LINEAR``, ``INC``, ``N10`` or ``SEND"..."`` one
each. So the manual's four-axis line ``X1000 Y1200 Z1400 A1600`` takes 4 words and 100 of
them 400. A line always takes at least one word. ``[INF]`` the manual does not say what a
value-less word costs; one word is the simplest rule that agrees with its example.

Operations (``ops``) are small tuples, in program order, executed by the coordinate system's
move planning (:mod:`motionsim.sim.pmac.lookahead`). The axis words of a line (with its circle
vector words) form **one move**, executed at the end of the line — or before a ``DWELL``/``DELAY``
in the same line — after the line's modal settings (``X10 Y10 F5`` moves at F5, as in the manual's
``&1 X10 Y10 F5`` example). Assignments keep their place relative to that move.
"""

from __future__ import annotations

from typing import Any

from ...errors import NotSimulated, ParseError
from ..language import flow_statements as fl
from ..language import statements as st
from ..language.axis_definitions import Frax
from ..language.compiled import (
    OP_ASSIGN,
    OP_AXISMODE,
    OP_DELAY,
    OP_DWELL,
    OP_FRAX,
    OP_HOME,
    OP_MODAL,
    OP_MODE,
    OP_MOVE,
    OP_PSET,
    OP_SEND,
    ProgramLine,
)
from ..language.expressions import constant
from ..language.fast_line import fast_compile
from ..language.flow_statements import FLOW_TYPES
from ..language.motor_statements import HomeList
from ..language.parser import parse_program_line
from ..language.ranges import RangeAssign

#: Statements that make a line a control-flow line (:attr:`ProgramLine.flow`).
_MARKS = (st.Label, *FLOW_TYPES)


def compile_statements(text: str, stmts: list[Any]) -> ProgramLine:
    """Compile program statements (already parsed) into a :class:`ProgramLine`."""
    ops: list[tuple[Any, ...]] = []
    modal: list[tuple[Any, ...]] = []
    axes: list[tuple[str, Any]] = []
    vectors: list[tuple[str, Any]] = []
    velocities: list[tuple[str, Any]] = []
    moves = 0
    words = len(stmts)
    flow = None
    jumps = False  # control flow, not only labels: the line is never a planning short cut

    def flush() -> None:
        nonlocal moves
        ops.extend(modal)
        modal.clear()
        if axes or vectors:
            ops.append((OP_MOVE, tuple(axes), tuple(vectors), tuple(velocities)))
            moves += 1
            axes.clear()
            vectors.clear()
            velocities.clear()

    for s in stmts:
        if isinstance(s, st.AxisWord):
            axes.append((s.axis, s.value))
            if s.velocity is not None:
                velocities.append((s.axis, s.velocity))
                words += 1  # position and velocity: two values, two words [INF]
        elif isinstance(s, st.VectorWord):
            vectors.append((s.name, s.value))
        elif isinstance(s, st.Modal):
            modal.append((OP_MODAL, s.name, s.value))
        elif isinstance(s, st.MoveMode):
            modal.append((OP_MODE, s.mode))
        elif isinstance(s, st.PvtMode):
            modal.append((OP_MODE, "PVT"))
            modal.append((OP_MODAL, "TM", s.ms))  # the move-time register (I42 = 0)
        elif isinstance(s, st.AxisMode):
            modal.append((OP_AXISMODE, s.incremental, s.axes))
        elif isinstance(s, Frax):
            modal.append((OP_FRAX, s.axes))
        elif isinstance(s, RangeAssign):  # one assignment per variable of the range
            ops.extend((OP_ASSIGN, s.kind, constant(float(n)), "=", s.value) for n in s.numbers)
        elif isinstance(s, st.Assign):
            ops.append((OP_ASSIGN, s.target.kind, s.target.index, s.op, s.value))
        elif isinstance(s, st.Dwell):
            flush()
            ops.append((OP_DWELL, s.ms))
            moves += 1
        elif isinstance(s, st.Delay):
            flush()
            ops.append((OP_DELAY, s.ms))
            moves += 1
        elif isinstance(s, st.PSet):
            flush()
            ops.append((OP_PSET, s.axes))
            words += len(s.axes) - 1  # one word per value, like axis words [INF]
        elif isinstance(s, HomeList):
            flush()
            ops.append((OP_HOME, s.motors, s.zero))
            moves += 1
            words += len(s.motors) - 1  # one word per motor, like axis words [INF]
        elif isinstance(s, _MARKS):
            flow = tuple(stmts)  # labels and control flow: split by .flow when run
            jumps = jumps or isinstance(s, FLOW_TYPES)
        elif isinstance(s, st.Message) and s.kind == "SEND":
            ops.append((OP_SEND, s.port, s.text))
        # CMD messages: stored, no action.
    flush()
    simple = None
    if (
        not jumps  # a control-flow line is split by .flow first: never a short cut
        and len(ops) == 1
        and ops[0][0] == OP_MOVE
        and not ops[0][2]
        and not ops[0][3]
        and all(e.const is not None for _, e in ops[0][1])
    ):
        simple = tuple((a, float(e.const)) for a, e in ops[0][1])
    simple_pvt = None
    if (
        not jumps
        and len(ops) == 1
        and ops[0][0] == OP_MOVE
        and not ops[0][2]
        and all(e.const is not None for _, e in ops[0][1])
        and all(e.const is not None for _, e in ops[0][3])
    ):
        vel = {a: float(e.const) for a, e in ops[0][3]}
        simple_pvt = tuple((a, float(e.const), vel.get(a, 0.0)) for a, e in ops[0][1])
    return ProgramLine(text, max(1, words), tuple(ops), moves, simple, simple_pvt, flow)


def compile_line(text: str) -> ProgramLine:
    """Parse and compile one rotary-buffer line.

    Raises:
        sim.errors.ParseError: positioned (column), ERR003.
        sim.errors.NotSimulated: control flow in a rotary buffer (:func:`rotary_check`).
    """
    line = fast_compile(text)
    if line is not None:
        return line
    line = compile_statements(text, parse_program_line(text))
    rotary_check(line)
    return line


#: Control flow a rotary line may hold: the one-line IF and calls of fixed programs (CALL,
#: G/M/T/D codes), which return to the rotary buffer.
_ROTARY_FLOW = (fl.If, fl.Call)
#: Multi-line control flow: the line to jump to may not be in the buffer yet (PUM p162).
_MULTI_LINE = (fl.Else, fl.EndIf, fl.While, fl.EndWhile)


def rotary_check(line: ProgramLine) -> None:
    """What control flow a rotary line may hold, decided before anything is stored.

    "In rotary program buffers single-line condition actions are the only types of
    conditional statements permitted" (PUM p162): ``IF ({condition}) {statements}`` on one
    line; a multi-line ``IF`` / ``ELSE`` / ``ENDIF`` / ``WHILE`` / ``ENDWHILE`` is refused
    (ERR003). ``CALL`` and the G/M/T/D codes call fixed programs and come back to the next
    statement (TSRM p416, p425): simulated. ``GOTO``, ``GOSUB`` (labels of a rotary buffer
    are freed as they run), ``RETURN``, ``READ``, ``STOP``, ``WAIT``, ``BLOCKSTART`` /
    ``BLOCKSTOP`` in a rotary line are not simulated ``[INF]`` and say so by name.

    Raises:
        ParseError: ERR003, multi-line control flow.
        NotSimulated: ERR003 on the wire, naming the statement.
    """
    stmts = line.flow
    if stmts is None:
        return
    for s in stmts:
        column = getattr(s, "column", None)
        if isinstance(s, _MULTI_LINE) or (isinstance(s, fl.If) and not s.inline):
            raise ParseError(
                f"{type(s).__name__.upper()}: a rotary buffer takes only the one-line IF "
                "({condition}) {statements} (PUM p162)",
                pmac_error="ERR003", column=column, text=line.text,
            )
        if isinstance(s, FLOW_TYPES) and not isinstance(s, _ROTARY_FLOW):
            raise NotSimulated(
                f"{type(s).__name__.upper()} in a rotary buffer is valid Turbo PMAC that "
                "motionsim does not simulate (CALL, G/M/T/D codes and the one-line IF are)",
                pmac_error="ERR003", column=column, text=line.text,
            )


__all__ = [
    "OP_ASSIGN",
    "OP_AXISMODE",
    "OP_DELAY",
    "OP_DWELL",
    "OP_MODAL",
    "OP_MODE",
    "OP_MOVE",
    "OP_FRAX",
    "OP_HOME",
    "OP_PSET",
    "OP_SEND",
    "ProgramLine",
    "compile_line",
    "compile_statements",
    "rotary_check",
]
