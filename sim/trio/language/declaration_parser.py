"""Parsing the statements the MC4 language adds — ``INCLUDE``, ``DIM``, ``GLOBAL``,
``CONSTANT`` — and ``ON``: ``ON BASICERROR GOTO label`` and ``ON expr GOSUB / GOTO l1, ...``
(spec trio.md §11.2–§11.4). A mixin of :class:`motionsim.sim.trio.language.parser._Line`,
whose token helpers (``accept``, ``expect``, ``name``, ``string``, ``expr`` ...) it uses;
``INCLUDE`` .. ``CONSTANT`` are rows of the ``mc4xx`` statement table only (``parser.MC4``),
``ON`` a row of every model's.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from typing import Any

from ...errors import ParseError
from ..card.basic_errors import BasicError
from ..card.data_memory import too_big
from . import statements as s
from .expressions import FUNCTIONS, compile_expr
from .names import label, variable
from .strings import DEFAULT_LENGTH

#: DIM types (MC4, spec §11.4).
TYPES = ("INTEGER", "FLOAT", "STRING", "BOOLEAN")
#: Dimensions of a DIM array: ``DIM s AS INTEGER(32, 3)`` is the deepest form real MC4xx
#: programs write; no manual figure was reachable ``[INF]``.
MAX_DIMENSIONS = 2


class DeclarationParser:
    """``st_ON``, ``st_INCLUDE``, ``st_DIM``, ``st_GLOBAL``, ``st_CONSTANT``."""

    i: int
    accept: Callable[[str], bool]
    at: Callable[[str], bool]
    expect: Callable[[str], Any]
    error: Callable[..., ParseError]
    peek: Callable[..., Any]
    col: Callable[[], int]
    name: Callable[[], str]
    string: Callable[..., str]
    expr: Callable[..., s.Expr]
    reserved: Callable[[str], bool]
    variable_name: Callable[..., str]

    def st_ON(self, ln: int, col: int) -> s.Stmt:
        """``ON BASICERROR GOTO label`` or ``ON expr GOSUB|GOTO l1, l2, ...``."""
        if self.accept("BASICERROR"):
            if not self.accept("GOTO"):
                raise self.error("ON BASICERROR needs GOTO and a label")
            if self.peek()[0] != "name":
                raise self.error("ON BASICERROR GOTO needs the label of the error handler")
            return s.OnError(ln, col, label(self.name()))
        value = self.expr()
        if self.accept("GOSUB"):
            gosub = True
        elif self.accept("GOTO"):
            gosub = False
        else:
            raise self.error("ON expr needs GOSUB or GOTO and a list of labels")
        labels = [label(self.name())]
        while self.accept(","):
            labels.append(label(self.name()))
        return s.OnBranch(ln, col, value, tuple(labels), gosub)

    def st_INCLUDE(self, ln: int, col: int) -> s.Stmt:
        return s.Include(ln, col, self.string())

    def st_DIM(self, ln: int, col: int) -> s.Stmt:
        """``DIM name[(n[, m])][, name2 ...] AS INTEGER|FLOAT|STRING[(length)]|BOOLEAN
        [= value]`` (spec §11.4): one type for every name of the line; ``AS FLOAT(n[, m])``
        gives the names without their own sizes that array shape ``[INF]`` (spec §2.5);
        ``= value`` sets each name when its DIM runs (an array cannot take one ``[INF]``)."""
        names: list[tuple[str, int, tuple[int, ...]]] = []
        while True:
            c = self.col()
            name = self.variable_name()
            names.append((name, c, self.dimensions() if self.at("(") else ()))
            if not self.accept(","):
                break
        self.expect("AS")
        tok = self.peek()
        kind = self.name() if tok[0] == "name" else ""
        if kind not in TYPES:
            raise self.error(f"DIM needs a type ({', '.join(TYPES)})", tok[2])
        length: int | None = None
        shape: tuple[int, ...] = ()
        if self.at("("):
            if kind == "STRING":
                self.i += 1
                length = self.whole_number("string length")
                self.expect(")")
            else:
                shape = self.dimensions()  # DIM x AS FLOAT(n): an array of n ([INF], §2.5)
        init = None
        if self.accept("="):
            c = self.col()
            init = self.expr()
            if shape or any(d for _n, _c, d in names):
                raise self.error("an array cannot take an initial value in its DIM", c)
        dims: list[s.Dim] = []
        for name, c, own in names:
            if own and shape:
                raise self.error(f"the array size of {name} is given twice", c)
            shape_of = own or shape
            size = math.prod(shape_of) if shape_of else None
            why = too_big(kind, size, length or DEFAULT_LENGTH)
            if why is not None:
                raise self.error(why, c)
            dims.append(s.Dim(ln, c if len(names) > 1 else col, name, kind, size, length,
                              shape_of, init))
        return dims[0] if len(dims) == 1 else s.DimList(ln, col, tuple(dims))

    def dimensions(self) -> tuple[int, ...]:
        """``(n)`` or ``(n, m)``: an array's sizes, whole numbers >= 1, at most
        :data:`MAX_DIMENSIONS` of them."""
        c = self.col()
        self.expect("(")
        out = [self.whole_number("array size")]
        while self.accept(","):
            out.append(self.whole_number("array size"))
        self.expect(")")
        if len(out) > MAX_DIMENSIONS:
            raise self.error(f"an array has at most {MAX_DIMENSIONS} dimensions, got {len(out)}",
                             c)
        return tuple(out)

    def whole_number(self, what: str) -> int:
        tok = self.peek()
        if tok[0] != "number" or not tok[1].isdigit() or int(tok[1]) < 1:
            raise self.error(f"expected a whole number >= 1 for the {what}")
        self.i += 1
        return int(tok[1])

    def st_GLOBAL(self, ln: int, col: int) -> s.Stmt:
        """``GLOBAL "name", vr``: the name of a VR for every program (spec §11.4)."""
        name, _c = self.declared_name()
        self.expect(",")
        tok = self.peek()
        if tok[0] != "number" or not tok[1].isdigit():
            raise self.error("GLOBAL needs the VR number (a whole number)")
        self.i += 1
        return s.Global(ln, col, name, int(tok[1]))

    def st_CONSTANT(self, ln: int, col: int) -> s.Stmt:
        """``CONSTANT "name", value``: a named number for every program (spec §11.4); also
        written with the bare name, ``CONSTANT name, value`` ``[INF]``. The value is any
        expression of numbers and the built-in constants (``2 * PI``, ``$FF``, ``-1``),
        worked out when the program is compiled."""
        name, _c = self.declared_name()
        self.expect(",")
        c = self.col()
        value = constant_value(self.expr())
        if value is None:
            raise self.error("CONSTANT needs a number known when the program is compiled "
                             "(numbers, PI, TRUE, FALSE, ON, OFF and operators)", c)
        return s.Constant(ln, col, name, value)

    def declared_name(self) -> tuple[str, int]:
        """The quoted name of GLOBAL / CONSTANT: an identifier that is not a keyword."""
        tok = self.peek()
        if tok[0] == "name":  # the bare form, CONSTANT name, value [INF]
            self.i += 1
            name = tok[1]
        else:
            name = self.string("name")
        if not re.fullmatch(r"[A-Z_][A-Z0-9_]*", name):
            raise self.error(f"{name!r} is not a valid variable name", tok[2])
        if self.reserved(name):
            raise self.error(f"{name} is a Trio BASIC keyword: it cannot be declared", tok[2])
        return variable(name), tok[2]


def constant_value(node: s.Expr) -> float | None:
    """The value of an expression of numbers alone (None if it needs anything else)."""
    if isinstance(node, s.Num):
        return node.value
    try:
        value = compile_expr(node)(None) if _numbers_only(node) else None
    except (BasicError, ArithmeticError, ValueError):
        return None
    return value if value is None or math.isfinite(value) else None


def _numbers_only(node: s.Expr) -> bool:
    if isinstance(node, s.Num):
        return True
    if isinstance(node, s.Unary):
        return _numbers_only(node.operand)
    if isinstance(node, s.Binary):
        return _numbers_only(node.left) and _numbers_only(node.right)
    if isinstance(node, s.Call) and node.name in FUNCTIONS:
        return all(_numbers_only(a) for a in node.args)
    return False


__all__ = ["MAX_DIMENSIONS", "TYPES", "DeclarationParser", "constant_value"]
