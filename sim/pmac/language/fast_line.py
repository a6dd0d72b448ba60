"""Fast path for the commonest streamed rotary-buffer lines: plain words with constant values.

A streaming host sends mostly lines such as ``X12.5 Y-3`` / ``INC LINEAR TA10 TS0 TM50`` /
``DWELL20`` / ``CIRCLE1 X1 Y2 I-1 J0``. For a line made only of

* axis words ``X Y Z A B C U V W``, vector words ``I J K R`` and the modal words
  ``F TA TS TM``, each with an optionally negated decimal constant,
* ``DWELL``/``DWE``, ``DELAY``/``DLY`` with such a constant,
* ``LINEAR``/``LIN``, ``RAPID``/``RPD``, ``INC``/``ABS`` (no axis list), ``CIRCLE1``/``CIRCLE2``,

or of one whole-line assignment of one or two plain operands (``P1=P2+1.5``, ``M12==1``, see
``_ASSIGN``), :func:`fast_compile` builds the
:class:`~motionsim.sim.pmac.buffers.program.ProgramLine`
directly from one regular-expression pass, with the same expressions (text, value) and
operations, in the same order, that :mod:`motionsim.sim.pmac.language.parser` and
:func:`~motionsim.sim.pmac.buffers.program.compile_statements` build. Any other line (variables in
words, longer expressions, comments, hex constants, PVT ``:v``, errors...) returns ``None`` and
takes the general parser, which alone reports errors: the fast path never raises. Tokens agree
with the general tokenizer because every word accepted here is the longest word of the general
word list at its position (a single letter followed by a number, sign or space cannot begin a
longer word, and a mode word is refused where the lexer would read a longer word, see
``_whole``). The equivalence is pinned by a property test
(``tests/sim/pmac/test_fast_line_properties.py``).
"""

from __future__ import annotations

import re
from typing import Any

from . import expressions as ex
from .compiled import (
    OP_ASSIGN,
    OP_AXISMODE,
    OP_DELAY,
    OP_DWELL,
    OP_MODAL,
    OP_MODE,
    OP_MOVE,
    ProgramLine,
)
from .parser import _WORDS as _LEXER_WORDS  # the general lexer's


def _whole(*words: str) -> str:
    """``words`` as an alternation, each only where the general lexer reads it whole: not
    followed by what would make it one of the lexer's longer words (``LIN`` not in ``LINK1``,
    which the lexer reads as the word ``LINK``). Derived from the lexer's own word list."""
    alts = []
    for w in words:
        longer = {g.upper()[len(w):] for g in _LEXER_WORDS if g.upper().startswith(w)} - {""}
        rests = [r"\s*".join(map(re.escape, r.split(" "))) for r in sorted(longer, key=len)]
        alts.append(w + (f"(?!{'|'.join(reversed(rests))})" if rests else ""))
    return "|".join(alts)


# Same number syntax as the general tokenizer (decimal only; ``$hex`` takes the general path).
_NUM = r"\d*\.\d+|\d+(?:\.(?!\.)\d*)?"
#: A valued word is followed by a number (after blanks and a sign), which no longer word of the
#: lexer continues a single letter with: checked here, so the letters stay one character class.
_LETTERS = "XYZABCUVWIJKRF"
if any(len(g) > 1 and g[0].upper() in _LETTERS and g[1] in " -.0123456789" for g in _LEXER_WORDS):
    raise RuntimeError("fast_line: a lexer word continues an axis letter with a number or blank")
_ITEM = (
    r"\s*(?:([" + _LETTERS + "]|" + _whole("DWELL", "DWE", "DELAY", "DLY", "TA", "TS", "TM")
    + r")\s*(-?)\s*(" + _NUM + r")"
    r"|(" + _whole("LINEAR", "LIN", "RAPID", "RPD", "INC", "ABS") + r")(?!\s*\()"
    r"|(?:" + _whole("CIRCLE", "CIR") + r")\s*([12])(?![\d.])"
    r"|(\S))"  # anything else: the line takes the general path
)
#: One pass over the line: every non-blank character is either in a plain item or is caught by
#: the last group, so the items found are contiguous and no check of positions is needed.
_ITEMS = re.compile(_ITEM, re.IGNORECASE | re.ASCII)

_OPERAND = r"(?:([PQMI])\s*(\d+)|(" + _NUM + r"))"
#: A whole-line assignment ``P1=P2+1.5``, ``M12==1``: a constant variable number, ``=`` (or an M
#: variable's synchronous ``==``) and a value of one or two operands (variables with constant
#: numbers, decimal constants), the first optionally negated.
_ASSIGN = re.compile(
    r"\s*([PQM])\s*(\d+)\s*(==|=)\s*(-?)\s*" + _OPERAND
    + r"\s*(?:([-+*/])\s*" + _OPERAND + r")?\s*",
    re.IGNORECASE | re.ASCII,
)

_findall = _ITEMS.findall
#: What a valued word is: 0 axis word, 1 circle vector word, 2 modal word, else its op code.
_KIND = {
    **dict.fromkeys("XYZABCUVW", 0), **dict.fromkeys("IJKR", 1),
    **dict.fromkeys(("F", "TA", "TS", "TM"), 2),
    "DWELL": OP_DWELL, "DWE": OP_DWELL, "DELAY": OP_DELAY, "DLY": OP_DELAY,
}  # fmt: skip
#: First characters of a whole-line assignment (``_ASSIGN``).
_ASSIGNS = frozenset("PQMpqm")
#: The op of each mode word (upper case; ops are tuples, shared by every line using them).
_MODE = {
    "LINEAR": (OP_MODE, "LINEAR"), "LIN": (OP_MODE, "LINEAR"),
    "RAPID": (OP_MODE, "RAPID"), "RPD": (OP_MODE, "RAPID"),
    "INC": (OP_AXISMODE, True, None), "ABS": (OP_AXISMODE, False, None),
}  # fmt: skip
_CIRCLE = {"1": (OP_MODE, "CIRCLE1"), "2": (OP_MODE, "CIRCLE2")}

def fast_compile(text: str) -> ProgramLine | None:
    """The compiled line when ``text`` has only the plain shapes above, else ``None``."""
    if text[:1] in _ASSIGNS:  # no plain word begins with P, Q or M: the line's first item
        return _assignment(text)  # would be "anything else", so go straight to the assignment
    items = _findall(text)
    if not items:
        return ProgramLine(text, 1, (), 0)
    if items[0][5]:
        return _assignment(text)
    expr = ex.Expr
    new = _new
    kind_of = _KIND.get
    ops: list[tuple[Any, ...]] = []
    modal: list[tuple[Any, ...]] = []
    axes: list[tuple[Any, ...]] = []
    vectors: list[tuple[Any, ...]] = []
    simple: list[tuple[str, float]] = []  # the axis words' values (the short cuts, below)
    simple_pvt: list[tuple[str, float, float]] = []  # the same with no end velocities
    moves = 0
    for word, neg, num, mode, circle, other in items:
        if word:
            kind = kind_of(word)
            if kind is None:  # lower or mixed case
                word = word.upper()
                kind = _KIND[word]
            # ex.constant(float(num), num), without the calls (the property test pins it):
            # the object made and its two slots stored here, no ``__init__`` frame (its
            # ``fn`` is left unset, as constant() leaves it); ``-n`` is what
            # ex.negate(ex.constant(n)) builds: text "-n", value -n.
            v = -float(num) if neg else float(num)
            e = new(expr)
            e.text = "-" + num if neg else num
            e.const = v
            if kind == 0:
                axes.append((word, e))
                simple.append((word, v))
                simple_pvt.append((word, v, 0.0))
            elif kind == 1:
                vectors.append((word, e))
            elif kind == 2:
                modal.append((OP_MODAL, word, e))
            else:
                ops.extend(modal)
                modal.clear()
                if axes or vectors:
                    ops.append((OP_MOVE, tuple(axes), tuple(vectors), ()))
                    moves += 1
                    axes.clear()
                    vectors.clear()
                ops.append((kind, e))
                moves += 1
        elif other:
            return None
        elif circle:
            modal.append(_CIRCLE[circle])
        else:
            op = _MODE.get(mode)
            modal.append(op if op is not None else _MODE[mode.upper()])
    if axes or vectors:
        move = (OP_MOVE, tuple(axes), tuple(vectors), ())
        if not ops and not modal and not vectors:  # the planners' short cuts (see ProgramLine)
            return _line(text, len(items), (move,), moves + 1, tuple(simple), tuple(simple_pvt))
        ops.extend(modal)
        ops.append(move)
        moves += 1
    else:
        ops.extend(modal)
    return _line(text, len(items), tuple(ops), moves, None, None)


#: ``object.__new__``: a class's instance with none of its slots set.
_new = object.__new__


def _line(
    text: str, words: int, ops: tuple[tuple[Any, ...], ...], moves: int,
    simple: tuple[tuple[str, float], ...] | None,
    simple_pvt: tuple[tuple[str, float, float], ...] | None,
) -> ProgramLine:
    """``ProgramLine(text, words, ops, moves, simple, simple_pvt)`` (no control flow), its
    slots stored here without the ``__init__`` frame (the property test pins it)."""
    line = _new(ProgramLine)
    line.text = text
    line.words = words
    line.ops = ops
    line.moves = moves
    line.simple = simple
    line.simple_pvt = simple_pvt
    line.flow = None
    return line


def _constant(value: float, text: str) -> ex.Expr:
    """``ex.constant(value, text)`` (``value`` a float already), made as the words' are: no
    ``Expr.__init__`` frame (the property test pins it)."""
    e = _new(ex.Expr)
    e.text = text
    e.const = value
    return e


def _operand(var: str, number: str, num: str) -> ex.Expr:
    if var:
        return ex.variable(var.upper(), _constant(float(int(number)), number))
    return _constant(float(num), num)


def _assignment(text: str) -> ProgramLine | None:
    m = _ASSIGN.fullmatch(text)
    if m is None:
        return None
    kind, index, op, neg, var1, n1, num1, binop, var2, n2, num2 = m.groups()
    kind = kind.upper()
    if op == "==" and kind != "M":
        return None
    for n in (index, n1, n2):
        if n is not None and int(n) > 8191:
            return None
    value = _operand(var1, n1, num1)
    if neg:
        value = ex.negate(value)
    if binop:
        value = ex.binary(binop, value, _operand(var2, n2, num2))
    target = _constant(float(int(index)), index)
    return _line(text, 1, ((OP_ASSIGN, kind, target, op, value),), 0, None, None)


__all__ = ["fast_compile"]
