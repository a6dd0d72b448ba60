"""Parsing the statements the MC4 language adds — ``INCLUDE``, ``DIM``, ``GLOBAL``,
``CONSTANT`` — and ``ON``: ``ON BASICERROR GOTO label`` and ``ON expr GOSUB / GOTO l1, ...``
(spec trio.md §11.2–§11.4). A mixin of :class:`motionsim.sim.trio.language.parser._Line`,
whose token helpers (``accept``, ``expect``, ``name``, ``string``, ``expr`` ...) it uses;
``INCLUDE`` .. ``CONSTANT`` are rows of the ``mc4xx`` statement table only (``parser.MC4``),
``ON`` a row of every model's.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import Any

from ...errors import ParseError
from ..card.data_memory import too_big
from . import statements as s
from .strings import DEFAULT_LENGTH

#: DIM types (MC4, spec §11.4).
TYPES = ("INTEGER", "FLOAT", "STRING", "BOOLEAN")


class DeclarationParser:
    """``st_ON``, ``st_INCLUDE``, ``st_DIM``, ``st_GLOBAL``, ``st_CONSTANT``."""

    i: int
    accept: Callable[[str], bool]
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
            if self.peek().kind != "name":
                raise self.error("ON BASICERROR GOTO needs the label of the error handler")
            return s.OnError(ln, col, self.name())
        value = self.expr()
        if self.accept("GOSUB"):
            gosub = True
        elif self.accept("GOTO"):
            gosub = False
        else:
            raise self.error("ON expr needs GOSUB or GOTO and a list of labels")
        labels = [self.name()]
        while self.accept(","):
            labels.append(self.name())
        return s.OnBranch(ln, col, value, tuple(labels), gosub)

    def st_INCLUDE(self, ln: int, col: int) -> s.Stmt:
        return s.Include(ln, col, self.string())

    def st_DIM(self, ln: int, col: int) -> s.Stmt:
        """``DIM name[(n)] AS INTEGER|FLOAT|STRING[(length)]|BOOLEAN`` (spec §11.4)."""
        name = self.variable_name()
        size = self.whole_number("array size") if self.accept("(") else None
        if size is not None:
            self.expect(")")
        self.expect("AS")
        tok = self.peek()
        kind = self.name() if tok.kind == "name" else ""
        if kind not in TYPES:
            raise self.error(f"DIM needs a type ({', '.join(TYPES)})", tok.col)
        length = None
        if self.accept("("):
            n = self.whole_number("string length" if kind == "STRING" else "array size")
            self.expect(")")
            if kind == "STRING":
                length = n
            elif size is None:
                size = n  # DIM x AS FLOAT(n): an array of n ([INF], spec §2.5)
            else:
                raise self.error("the array size is given twice")
        why = too_big(kind, size, length or DEFAULT_LENGTH)
        if why is not None:
            raise self.error(why, col)
        return s.Dim(ln, col, name, kind, size, length)

    def whole_number(self, what: str) -> int:
        tok = self.peek()
        if tok.kind != "number" or not tok.text.isdigit() or int(tok.text) < 1:
            raise self.error(f"expected a whole number >= 1 for the {what}")
        self.i += 1
        return int(tok.text)

    def st_GLOBAL(self, ln: int, col: int) -> s.Stmt:
        """``GLOBAL "name", vr``: the name of a VR for every program (spec §11.4)."""
        name, _c = self.declared_name()
        self.expect(",")
        tok = self.peek()
        if tok.kind != "number" or not tok.text.isdigit():
            raise self.error("GLOBAL needs the VR number (a whole number)")
        self.i += 1
        return s.Global(ln, col, name, int(tok.text))

    def st_CONSTANT(self, ln: int, col: int) -> s.Stmt:
        """``CONSTANT "name", value``: a named number for every program (spec §11.4)."""
        name, _c = self.declared_name()
        self.expect(",")
        c = self.col()
        value = self.expr()
        if not isinstance(value, s.Num):
            raise self.error("CONSTANT needs a number", c)
        return s.Constant(ln, col, name, value.value)

    def declared_name(self) -> tuple[str, int]:
        """The quoted name of GLOBAL / CONSTANT: an identifier that is not a keyword."""
        tok = self.peek()
        name = self.string("name")
        if not re.fullmatch(r"[A-Z_][A-Z0-9_]*", name):
            raise self.error(f"{name!r} is not a valid variable name", tok.col)
        if self.reserved(name):
            raise self.error(f"{name} is a Trio BASIC keyword: it cannot be declared", tok.col)
        return name, tok.col



__all__ = ["TYPES", "DeclarationParser"]
