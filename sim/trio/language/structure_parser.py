"""Parsing the structured statements of the MC4xx / MC6xx language: ``SELECT_CASE`` /
``CASE`` / ``CASE ELSE`` / ``END_CASE``, ``EXIT_LOOP``, and the ``FUNCTION`` ... ``ENDFUNC``
of a BASIC library with ``RETURN value`` (issue 32; rows of the ``mc4xx`` statement table,
``parser.MC4``). A mixin of :class:`motionsim.sim.trio.language.parser._Line`, whose token
helpers it uses; the compile side is :mod:`motionsim.sim.trio.language.structure` and
:mod:`motionsim.sim.trio.language.functions`.

Forms ``[BK]`` (the MC4 help pages of SELECT_CASE and EXIT_LOOP were not reachable; the
FUNCTION page as quoted on cnblogs "TRIO-basic指令--函数FUNCTION", httpcc/p/10748045):

* ``SELECT_CASE expr`` on its own line, then ``CASE v[, v ...]`` lines whose choices are
  values or ranges ``lo TO hi`` ``[INF]``, an optional ``CASE ELSE`` last, and ``END_CASE``;
* ``FUNCTION name([p1 AS type[, p2 AS type ...]]) [AS type]``: at most 16 parameters;
  parameters of one type may share it, ``(a, b AS INTEGER)`` (the help's "parameters of the
  same data type can be separated by commas"); a parameter left without a type at the end of
  the list is a FLOAT ``[INF]``; the return type is optional, at the end of the line.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ...errors import ParseError
from . import statements as s
from .declaration_parser import TYPES

#: Parameters a FUNCTION may have (FUNCTION help: "maximum of 16").
MAX_PARAMS = 16


class StructureParser:
    """``st_SELECT_CASE``, ``st_CASE``, ``st_END_CASE``, ``st_EXIT_LOOP``, ``st_FUNCTION``,
    ``st_ENDFUNC``."""

    i: int
    accept: Callable[[str], bool]
    at: Callable[[str], bool]
    expect: Callable[[str], Any]
    error: Callable[..., ParseError]
    peek: Callable[..., Any]
    col: Callable[[], int]
    name: Callable[[], str]
    expr: Callable[..., s.Expr]
    variable_name: Callable[..., str]
    end_of_statement: Callable[[], bool]

    def st_SELECT_CASE(self, ln: int, col: int) -> s.Stmt:
        if self.end_of_statement():
            raise self.error("SELECT_CASE needs the value the CASEs are compared with")
        return s.SelectCase(ln, col, self.expr())

    def st_CASE(self, ln: int, col: int) -> s.Stmt:
        if self.accept("ELSE"):
            return s.Case(ln, col, ())
        if self.end_of_statement():
            raise self.error("CASE needs a value, a range (lo TO hi) or ELSE")
        choices: list[tuple[s.Expr, s.Expr | None]] = []
        while True:
            low = self.expr()
            choices.append((low, self.expr() if self.accept("TO") else None))
            if not self.accept(","):
                return s.Case(ln, col, tuple(choices))

    def st_END_CASE(self, ln: int, col: int) -> s.Stmt:
        return s.EndCase(ln, col)

    def st_EXIT_LOOP(self, ln: int, col: int) -> s.Stmt:
        return s.ExitLoop(ln, col)

    def st_FUNCTION(self, ln: int, col: int) -> s.Stmt:
        name = self.variable_name("function name")
        params: list[tuple[str, str]] = []
        untyped: list[str] = []
        if self.accept("("):
            while not self.at(")"):
                c = self.col()
                pname = self.variable_name("parameter")
                if pname in untyped or any(p == pname for p, _t in params):
                    raise self.error(f"parameter {pname} is named twice", c)
                untyped.append(pname)
                if self.accept("AS"):
                    kind = self.type_name()
                    params.extend((p, kind) for p in untyped)
                    untyped.clear()
                if len(params) + len(untyped) > MAX_PARAMS:
                    raise self.error(f"a FUNCTION has at most {MAX_PARAMS} parameters", c)
                if not self.accept(","):
                    break
            self.expect(")")
            params.extend((p, "FLOAT") for p in untyped)  # [INF]
        returns = self.type_name() if self.accept("AS") else None
        return s.Function(ln, col, name, tuple(params), returns)

    def type_name(self) -> str:
        tok = self.peek()
        kind = self.name() if tok[0] == "name" else ""
        if kind not in TYPES:
            raise self.error(f"expected a type ({', '.join(TYPES)})", tok[2])
        return kind

    def st_ENDFUNC(self, ln: int, col: int) -> s.Stmt:
        return s.EndFunc(ln, col)

    def call_args(self) -> tuple[s.Expr, ...]:
        """``(a, b ...)`` or ``()``: an array element's indexes or a function's arguments."""
        self.expect("(")
        if self.accept(")"):
            return ()
        out = [self.expr()]
        while self.accept(","):
            out.append(self.expr())
        self.expect(")")
        return tuple(out)


__all__ = ["MAX_PARAMS", "StructureParser"]
