"""Trio BASIC expressions compiled to Python closures, and the controller's number format.

The controller compiles a program before running it (expressions to reverse Polish); here an
expression tree becomes one closure ``f(ctx) -> float`` so a running process does not walk the
tree again. Values are Python floats (the controller uses 32-bit floats; exact integers to
2**24 behave the same — bit-exact float32 rounding is not modelled).

Comparisons are fuzzy as on the controller: values closer than 1.19e-6 are equal. They yield
TRUE = -1 and FALSE = 0; AND, OR, XOR and NOT act bitwise on the integer value (NOT 0 = -1).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from motionsim.sim.trio import statements as s
from motionsim.sim.trio.basic_errors import DIVIDE_BY_ZERO, BasicError

Eval = Callable[[Any], float]

#: Difference below which two values compare equal (TJ1P-27).
FUZZ = 1.19e-6

TRUE = -1.0
FALSE = 0.0


def _sqr(x: float) -> float:
    if x < 0:
        raise BasicError(f"Parameter out of range: SQR({x:g})")
    return math.sqrt(x)


def _ln(x: float) -> float:
    if x <= 0:
        raise BasicError(f"Parameter out of range: LN({x:g})")
    return math.log(x)


#: Built-in functions: name -> (arity, implementation).
FUNCTIONS: dict[str, tuple[int, Callable[..., float]]] = {
    "ABS": (1, abs),
    "SQR": (1, _sqr),
    "INT": (1, lambda x: float(math.floor(x))),
    "FRAC": (1, lambda x: x - math.floor(x)),
    "SGN": (1, lambda x: float((x > 0) - (x < 0))),
    "SIN": (1, math.sin),
    "COS": (1, math.cos),
    "TAN": (1, math.tan),
    "ATAN": (1, math.atan),
    "ATAN2": (2, math.atan2),
    "EXP": (1, math.exp),
    "LN": (1, _ln),
}


def truth(value: float) -> bool:
    return value != 0.0


def _div(a: float, b: float) -> float:
    if b == 0.0:
        raise BasicError(DIVIDE_BY_ZERO)
    return a / b


def _mod(a: float, b: float) -> float:
    ib = int(b)
    if ib == 0:
        raise BasicError(DIVIDE_BY_ZERO)
    return float(int(a) % ib)


def _pow(a: float, b: float) -> float:
    try:
        r = a**b
    except (OverflowError, ZeroDivisionError):
        raise BasicError(DIVIDE_BY_ZERO) from None
    if isinstance(r, complex):
        raise BasicError(f"Parameter out of range: {a:g}^{b:g}")
    return float(r)


_BINARY: dict[str, Callable[[float, float], float]] = {
    "+": lambda a, b: a + b,
    "-": lambda a, b: a - b,
    "*": lambda a, b: a * b,
    "/": _div,
    "^": _pow,
    "MOD": _mod,
    "=": lambda a, b: TRUE if abs(a - b) < FUZZ else FALSE,
    "<>": lambda a, b: FALSE if abs(a - b) < FUZZ else TRUE,
    "<": lambda a, b: TRUE if a < b and abs(a - b) >= FUZZ else FALSE,
    ">": lambda a, b: TRUE if a > b and abs(a - b) >= FUZZ else FALSE,
    "<=": lambda a, b: TRUE if a <= b or abs(a - b) < FUZZ else FALSE,
    ">=": lambda a, b: TRUE if a >= b or abs(a - b) < FUZZ else FALSE,
    "AND": lambda a, b: float(int(a) & int(b)),
    "OR": lambda a, b: float(int(a) | int(b)),
    "XOR": lambda a, b: float(int(a) ^ int(b)),
}


def compile_expr(node: s.Expr) -> Eval:
    """A closure evaluating ``node`` against a running process' context.

    The context provides ``locals`` (dict), ``vr(i)``, ``table(i)`` and
    ``param(name, axis, proc)``; see :class:`motionsim.sim.trio.context.Context`.
    """
    if isinstance(node, s.Num):
        v = node.value
        return lambda c: v
    if isinstance(node, s.Local):
        name = node.name
        return lambda c: c.locals.get(name, 0.0)
    if isinstance(node, s.VrRef):
        idx = compile_expr(node.index)
        return lambda c: c.vr(idx(c))
    if isinstance(node, s.TableRef):
        idx = compile_expr(node.index)
        return lambda c: c.table(idx(c))
    if isinstance(node, s.Param):
        name = node.name
        axis = compile_expr(node.axis) if node.axis is not None else None
        proc = compile_expr(node.proc) if node.proc is not None else None
        if axis is None and proc is None:
            return lambda c: c.param(name, None, None)
        if proc is None:
            return lambda c: c.param(name, axis(c), None)
        return lambda c: c.param(name, axis(c) if axis else None, proc(c))
    if isinstance(node, s.Unary):
        inner = compile_expr(node.operand)
        if node.op == "-":
            return lambda c: -inner(c)
        return lambda c: float(~int(inner(c)))
    if isinstance(node, s.Binary):
        left, right = compile_expr(node.left), compile_expr(node.right)
        fn = _BINARY[node.op]
        if node.op == "+":
            return lambda c: left(c) + right(c)
        if node.op == "-":
            return lambda c: left(c) - right(c)
        if node.op == "*":
            return lambda c: left(c) * right(c)
        return lambda c: fn(left(c), right(c))
    if isinstance(node, s.Call):
        impl = FUNCTIONS[node.name][1]
        args = [compile_expr(a) for a in node.args]
        if len(args) == 1:
            (a,) = args
            return lambda c: float(impl(a(c)))
        return lambda c: float(impl(*(a(c) for a in args)))
    if isinstance(node, s.IoRead):
        io_name = node.name
        io_args = [compile_expr(a) for a in node.args]
        return lambda c: c.io_read(io_name, [a(c) for a in io_args])
    if isinstance(node, s.Str):
        raise TypeError("a string is not a number")
    raise TypeError(f"not an expression: {node!r}")


__all__ = ["FALSE", "FUNCTIONS", "FUZZ", "TRUE", "compile_expr", "truth"]
