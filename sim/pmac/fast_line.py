"""Fast path for the commonest streamed rotary-buffer lines: plain words with constant values.

A streaming host sends mostly lines such as ``X12.5 Y-3`` / ``INC LINEAR TA10 TS0 TM50`` /
``DWELL20`` / ``CIRCLE1 X1 Y2 I-1 J0``. For a line made only of

* axis words ``X Y Z A B C U V W``, vector words ``I J K R`` and the modal words
  ``F TA TS TM``, each with an optionally negated decimal constant,
* ``DWELL``/``DWE``, ``DELAY``/``DLY`` with such a constant,
* ``LINEAR``/``LIN``, ``RAPID``/``RPD``, ``INC``/``ABS`` (no axis list), ``CIRCLE1``/``CIRCLE2``,

:func:`fast_compile` builds the :class:`~motionsim.sim.pmac.program.ProgramLine` directly from one
regular-expression pass, with the same expressions (text, value) and operations, in the same
order, that :mod:`motionsim.sim.pmac.parser` and
:func:`~motionsim.sim.pmac.program.compile_statements` build. Any other line (variables,
expressions, comments, hex constants, PVT ``:v``, errors...) returns ``None`` and takes the
general parser, which alone reports errors: the fast path never raises. Tokens agree with the
general tokenizer because every word accepted here is the longest word of the general word list
at its position (a single letter followed by a number, sign or space cannot begin a longer
word). The equivalence is pinned by a property test
(``tests/sim/pmac/test_fast_line_properties.py``).
"""

from __future__ import annotations

import re

from motionsim.sim.pmac import expressions as ex
from motionsim.sim.pmac.program import (
    OP_AXISMODE,
    OP_DELAY,
    OP_DWELL,
    OP_MODAL,
    OP_MODE,
    OP_MOVE,
    ProgramLine,
)

# Same number syntax as the general tokenizer (decimal only; ``$hex`` takes the general path).
_NUM = r"\d*\.\d+|\d+(?:\.(?!\.)\d*)?"
_ITEM = (
    r"\s*(?:(DWELL|DWE|DELAY|DLY|TA|TS|TM|[XYZABCUVWIJKRF])\s*(-?)\s*(" + _NUM + r")"
    r"|(LINEAR|LIN|RAPID|RPD|INC|ABS)(?!\s*\()"
    r"|(?:CIRCLE|CIR)\s*([12])(?![\d.])"
    r"|(\S))"  # anything else: the line takes the general path
)
#: One pass over the line: every non-blank character is either in a plain item or is caught by
#: the last group, so the items found are contiguous and no check of positions is needed.
_ITEMS = re.compile(_ITEM, re.IGNORECASE | re.ASCII)

_AXES = frozenset("XYZABCUVW")
_VECTORS = frozenset("IJKR")
_MODE = {"LINEAR": "LINEAR", "LIN": "LINEAR", "RAPID": "RAPID", "RPD": "RAPID"}
_TIMED = {"DWELL": OP_DWELL, "DWE": OP_DWELL, "DELAY": OP_DELAY, "DLY": OP_DELAY}


def fast_compile(text: str) -> ProgramLine | None:
    """The compiled line when ``text`` has only the plain shapes above, else ``None``."""
    constant = ex.constant
    ops: list[tuple] = []
    modal: list[tuple] = []
    axes: list[tuple] = []
    vectors: list[tuple] = []
    moves = 0
    items = _ITEMS.findall(text)
    for word, neg, num, mode, circle, other in items:
        if other:
            return None
        if word:
            w = word.upper()
            e = constant(float(num), num)
            if neg:
                e = ex.negate(e)
            if w in _AXES:
                axes.append((w, e))
            elif w in _VECTORS:
                vectors.append((w, e))
            elif w in _TIMED:
                ops.extend(modal)
                modal.clear()
                if axes or vectors:
                    ops.append((OP_MOVE, tuple(axes), tuple(vectors), ()))
                    moves += 1
                    axes.clear()
                    vectors.clear()
                ops.append((_TIMED[w], e))
                moves += 1
            else:
                modal.append((OP_MODAL, w, e))
        elif circle:
            modal.append((OP_MODE, "CIRCLE" + circle))
        else:
            m = mode.upper()
            if m in _MODE:
                modal.append((OP_MODE, _MODE[m]))
            else:
                modal.append((OP_AXISMODE, m == "INC", None))
    ops.extend(modal)
    if axes or vectors:
        move = (OP_MOVE, tuple(axes), tuple(vectors), ())
        ops.append(move)
        moves += 1
        if len(ops) == 1 and not vectors:  # the planners' short cuts (see ProgramLine)
            simple = tuple((a, e.const) for a, e in axes)
            simple_pvt = tuple((a, e.const, 0.0) for a, e in axes)
            return ProgramLine(text, max(1, len(items)), (move,), moves, simple, simple_pvt)
    return ProgramLine(text, max(1, len(items)), tuple(ops), moves)


__all__ = ["fast_compile"]
