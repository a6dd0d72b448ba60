"""Turbo PMAC arithmetic, compiled once at parse time (spec §10, TUM p248, TSRM p486-489).

An expression is compiled to a closure ``fn(vars, cs) -> float`` (``vars`` is the controller's
:class:`motionsim.sim.pmac.card.variables.Variables`, ``cs`` the coordinate system whose Q bank is
meant), so evaluating a stored line costs a few Python calls. A constant expression also keeps its
value in ``Expr.const`` so the hot path can skip the call entirely.

The manual's rules modelled here:

* two priority levels only: ``* / % &`` above ``+ - | ^``; equal levels left to right;
* unary minus negates; a unary plus is an error (TSRM p486);
* ``/`` is floating point; dividing by zero saturates at ±2**47 (0/0 gives 0) and the program
  goes on;
* ``%`` truncates the quotient toward -inf: for a positive divisor n the result is in [0, n),
  for a negative divisor n in [-|n|, |n|) (``11%-4`` = 3, ``-11%-4`` = -3); ``x%0`` = 0;
* ``& | ^`` act bit by bit on the two's-complement fixed-point form, fractional bits included
  (``0.5^0.875`` = 0.375, ``3^-3`` = -2); we keep 24 fractional bits;
* functions ``SIN COS TAN ASIN ACOS ATAN ATAN2 LN EXP SQRT ABS INT`` (``INT`` toward -inf);
  angles in degrees when I15 = 0 (default), radians when I15 = 1; ``ATAN2(y)`` takes its cosine
  argument from Q0 of the coordinate system ``[INF]``.

Bounds of this model (the card evaluates on a fixed-size stack; the manual gives no figure, so
the figures are ours ``[INF]``): an expression nests at most :data:`MAX_NESTING` levels of
parentheses, function calls, variable indexes and unary minus signs (level ``MAX_NESTING + 1``
is ERR003 naming the limit), so that neither the parser nor a compiled line recurses deeper
than Python's stack allows whatever the entry (terminal, Ethernet, PLC, motion program,
kinematics). A long run of operators of one level (``P1+P2+...``) is not nesting: it compiles
to one loop (:func:`chain`) whose length only the line and program size limits bound.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

Fn = Callable[[Any, int], float]

#: The deepest nesting of ``( )``, ``FUNC( )``, ``P( )`` indexes and unary ``-`` one expression
#: may have ``[INF]``; one more level is ERR003 (:mod:`motionsim.sim.pmac.language.parser`).
MAX_NESTING = 32
#: Runs of this many operands or fewer compile to nested closures (the fast path of streamed
#: lines); longer runs compile to one loop so evaluation depth does not grow with length.
_NESTED_CHAIN = 8

#: Division by zero saturates here (TSRM p487).
SATURATION = float(2**47)
_FRAC = float(1 << 24)


def pmac_div(a: float, b: float) -> float:
    """Floating-point division with the controller's saturation at ±2**47."""
    if b == 0:
        return 0.0 if a == 0 else math.copysign(SATURATION, a)
    return a / b


def pmac_mod(a: float, n: float) -> float:
    """The controller's modulo (TSRM p487): see the module docstring."""
    if n == 0:
        return 0.0
    if n > 0:
        return a - math.floor(a / n) * n
    m = -n
    r = a - math.floor(a / (2 * m)) * (2 * m)
    return r - 2 * m if r >= m else r


def _fixed(x: float) -> int:
    return math.floor(x * _FRAC)


def pmac_and(a: float, b: float) -> float:
    return (_fixed(a) & _fixed(b)) / _FRAC


def pmac_or(a: float, b: float) -> float:
    return (_fixed(a) | _fixed(b)) / _FRAC


def pmac_xor(a: float, b: float) -> float:
    return (_fixed(a) ^ _fixed(b)) / _FRAC


BINARY: dict[str, Callable[[float, float], float]] = {
    "+": lambda a, b: a + b,
    "-": lambda a, b: a - b,
    "*": lambda a, b: a * b,
    "/": pmac_div,
    "%": pmac_mod,
    "&": pmac_and,
    "|": pmac_or,
    "^": pmac_xor,
}

#: Operators of the higher priority level; the rest are the lower level.
HIGH = frozenset("*/%&")
LOW = frozenset("+-|^")


def _deg(vars_: Any) -> bool:
    return vars_.angles_in_degrees()


def _sin(v: Any, x: float) -> float:
    return math.sin(math.radians(x) if _deg(v) else x)


def _cos(v: Any, x: float) -> float:
    return math.cos(math.radians(x) if _deg(v) else x)


def _tan(v: Any, x: float) -> float:
    return math.tan(math.radians(x) if _deg(v) else x)


def _inv(fn: Callable[[float], float]) -> Callable[[Any, float], float]:
    def f(v: Any, x: float) -> float:
        try:
            r = fn(x)
        except ValueError:
            return 0.0
        return math.degrees(r) if _deg(v) else r

    return f


def _safe(fn: Callable[[float], float]) -> Callable[[Any, float], float]:
    def f(v: Any, x: float) -> float:
        try:
            return fn(x)
        except (ValueError, OverflowError):
            return 0.0

    return f


#: ``NAME(expr)`` functions: ``f(vars, x)``. ATAN2 is special-cased (needs Q0).
FUNCTIONS: dict[str, Callable[[Any, float], float]] = {
    "SIN": _sin,
    "COS": _cos,
    "TAN": _tan,
    "ASIN": _inv(math.asin),
    "ACOS": _inv(math.acos),
    "ATAN": _inv(math.atan),
    "LN": _safe(math.log),
    "EXP": _safe(math.exp),
    "SQRT": _safe(math.sqrt),
    "ABS": lambda v, x: abs(x),
    "INT": lambda v, x: float(math.floor(x)),
    "ATAN2": lambda v, x: 0.0,  # replaced in compile_function
}


@dataclass(eq=True, unsafe_hash=True, slots=True)
class Expr:
    """A compiled expression: ``text`` as written, ``const`` when it has no variables.

    Immutable once built (compiled lines are cached and shared), but not a frozen dataclass:
    every streamed word builds one, and a frozen class's fields can only be set through
    ``object.__setattr__`` or the slot descriptors, which cost a third of a streamed line's
    parse; plain slot stores in ``__init__`` do not. Equality and hash are the frozen
    class's (``text`` and ``const``)."""

    text: str
    fn: Fn = field(compare=False, repr=False)
    const: float | None = None

    def __init__(self, text: str, fn: Fn | None, const: float | None = None) -> None:
        self.text = text
        if fn is not None:
            self.fn = fn
        self.const = const

    def __getattr__(self, name: str) -> Fn:
        """A constant's ``fn`` is made when first asked for (:func:`constant` leaves it
        unset: most constants are only ever read through ``const``, and a closure per
        streamed word was a tenth of a line's parse)."""
        if name == "fn":
            const = self.const
            if const is not None:
                def fn(_v: Any, _c: int) -> float:
                    return const

                self.fn = fn
                return fn
        raise AttributeError(name)

    def __call__(self, vars_: Any, cs: int) -> float:
        return self.const if self.const is not None else self.fn(vars_, cs)


def too_deep(text: str) -> int | None:
    """The 1-based column of the first ``(`` that opens level ``MAX_NESTING + 1`` in ``text``
    (quoted ``"..."`` text and ``;`` comments skipped), or None: the bound checked on a whole
    line before any recursive parse of it (a PLC condition's sub-conditions)."""
    depth = 0
    quoted = False
    for i, ch in enumerate(text):
        if ch == '"':
            quoted = not quoted
        elif quoted:
            continue
        elif ch == ";":
            return None
        elif ch == "(":
            depth += 1
            if depth > MAX_NESTING:
                return i + 1
        elif ch == ")":
            depth -= 1
    return None


def constant(value: float, text: str | None = None) -> Expr:
    """An expression that is just a number."""
    v = float(value)
    return Expr(text if text is not None else repr(v), None, v)  # fn: made when asked for


def binary(op: str, left: Expr, right: Expr) -> Expr:
    """``left op right``; folded when both sides are constant."""
    f = BINARY[op]
    text = f"{left.text}{op}{right.text}"
    if left.const is not None and right.const is not None:
        return constant(f(left.const, right.const), text)
    lc, rc = left.const, right.const
    if rc is not None:  # ``P1+1.5``: the constant side read as its value (no fn made for it)
        lf = left.fn
        return Expr(text, lambda v, c: f(lf(v, c), rc))
    if lc is not None:
        rf = right.fn
        return Expr(text, lambda v, c: f(lc, rf(v, c)))
    lf, rf = left.fn, right.fn
    return Expr(text, lambda v, c: f(lf(v, c), rf(v, c)))


def chain(first: Expr, rest: list[tuple[str, Expr]]) -> Expr:
    """``first op1 e1 op2 e2 ...`` of one priority level, left to right.

    Equal to folding :func:`binary` over the run (the same text, the same constant folding of
    a constant prefix, the same order of evaluation), but a long run is one closure looping
    over its operands, so neither building its text nor evaluating it grows Python's stack or
    costs quadratic time."""
    if len(rest) < _NESTED_CHAIN:
        left = first
        for op, right in rest:
            left = binary(op, left, right)
        return left
    k = 0
    left = first
    while k < len(rest) and left.const is not None and rest[k][1].const is not None:
        op, right = rest[k]
        left = constant(BINARY[op](left.const, right.const), "")
        k += 1
    parts = [first.text]
    for op, right in rest:
        parts.append(op)
        parts.append(right.text)
    text = "".join(parts)
    if k == len(rest):
        return constant(left.const, text)  # type: ignore[arg-type]
    head = left
    steps = [(BINARY[op], right.fn) for op, right in rest[k:]]

    def run(v: Any, c: int) -> float:
        acc = head.fn(v, c)
        for f, rf in steps:
            acc = f(acc, rf(v, c))
        return acc

    return Expr(text, run)


def negate(inner: Expr) -> Expr:
    text = f"-{inner.text}"
    if inner.const is not None:
        return constant(-inner.const, text)
    f = inner.fn
    return Expr(text, lambda v, c: -f(v, c))


def paren(inner: Expr) -> Expr:
    if inner.const is not None:
        return Expr(f"({inner.text})", None, inner.const)  # (fn made when asked for)
    return Expr(f"({inner.text})", inner.fn)


def variable(kind: str, index: Expr) -> Expr:
    """A variable read ``I5``, ``P(P1+2)``; ``kind`` is one of I P Q M (upper case)."""
    text = f"{kind}{index.text}"
    if index.const is not None:
        n = int(index.const)
        return Expr(text, lambda v, c: v.read(kind, n, c))
    f = index.fn
    return Expr(text, lambda v, c: v.read(kind, int(f(v, c)), c))


def function(name: str, arg: Expr) -> Expr:
    """``NAME(arg)``."""
    text = f"{name}({arg.text})"
    af = arg.fn
    if name == "ATAN2":

        def atan2(v: Any, c: int) -> float:
            r = math.atan2(af(v, c), v.read("Q", 0, c))
            return math.degrees(r) if _deg(v) else r

        return Expr(text, atan2)
    f = FUNCTIONS[name]
    return Expr(text, lambda v, c: f(v, af(v, c)))


__all__ = [
    "BINARY",
    "FUNCTIONS",
    "HIGH",
    "LOW",
    "MAX_NESTING",
    "SATURATION",
    "Expr",
    "binary",
    "chain",
    "constant",
    "function",
    "negate",
    "paren",
    "pmac_div",
    "pmac_mod",
    "too_deep",
    "variable",
]
