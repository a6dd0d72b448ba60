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

from ..card.basic_errors import DIVIDE_BY_ZERO, BasicError
from ..card.fieldbus import BUS_FUNCTIONS
from . import statements as s
from .scope import Decl, ExprError, Scope
from .strings import STRING_FUNCTIONS, arg_kinds

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


def _shift(a: float, b: float, left: bool) -> float:
    """``a << b`` / ``a >> b``: the integer part of ``a`` shifted by the integer part of ``b``
    bits (``>>`` keeps the sign, an arithmetic shift ``[INF]``); a count below 0 or above 63
    (the MC4 integer is 64-bit) is a run-time error ``[INF]``."""
    n = int(b)
    if not 0 <= n <= 63:
        raise BasicError(f"Parameter out of range: shift by {b:g} bits")
    return float(int(a) << n) if left else float(int(a) >> n)


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
    "<<": lambda a, b: _shift(a, b, True),
    ">>": lambda a, b: _shift(a, b, False),
}


#: Expressions that are numbers whatever their operands (a caller may skip kind_of for them).
ALWAYS_NUM = frozenset({s.Num, s.VrRef, s.TableRef, s.Param, s.Unary, s.Bit, s.IoRead})


def kind_of(node: s.Expr, scope: Scope | None = None) -> str:
    """``"str"`` for an expression whose value is text (MC4 strings), else ``"num"``."""
    cls = node.__class__
    if cls in ALWAYS_NUM:
        return "num"
    if cls is s.Str:
        return "str"
    if isinstance(node, (s.Local, s.Element)) and scope is not None:
        decl = scope.get(node.name)
        if decl is None:
            fn = scope.function(node.name) if scope.functions else None
            return "str" if fn is not None and fn.is_str else "num"
        return "str" if decl.is_str else "num"
    if isinstance(node, s.Call) and node.name in STRING_FUNCTIONS:
        return STRING_FUNCTIONS[node.name][3]
    if isinstance(node, s.Binary) and node.op == "+":
        return "str" if kind_of(node.left, scope) == "str" else "num"
    return "num"


def _mismatch(what: str) -> ExprError:
    return ExprError(f"type mismatch: {what}")


def _num(node: s.Expr, scope: Scope | None, what: str) -> Eval:
    cls = node.__class__
    if cls not in ALWAYS_NUM and kind_of(node, scope) == "str":
        raise _mismatch(f"{what} needs a number, not a string")
    return _COMPILE[cls](node, scope)


def _call(node: s.Local | s.Element, scope: Scope) -> Eval | None:
    """A call of a library function (:mod:`.functions`) when the name is one, else None."""
    fn = scope.function(node.name)
    if fn is None:
        return None
    from .functions import call_of

    scope.used.add(fn.library)
    args = node.indices if isinstance(node, s.Element) else ()
    return call_of(fn, args, scope, value=True)


def _local(node: s.Local, scope: Scope | None) -> Eval:
    name = node.name
    call = _call(node, scope) if scope is not None and scope.functions else None
    if call is not None:
        return call
    decl = scope.plain(name) if scope is not None else None
    if decl is None:
        reader = _SHARED.get(name)  # a str key: a local's reader (a constant's is a tuple)
        return reader if reader is not None else _remember(
            name, lambda c: c.locals.get(name, 0.0))
    if decl.kind == "GLOBAL":
        index = float(decl.index)
        return lambda c: c.vr(index)
    if decl.kind == "CONSTANT":
        value = decl.value
        return lambda c: value
    if decl.size is not None:
        raise ExprError(f"{name} is an array: it needs an index, {name}(i)")
    initial = decl.initial()
    return lambda c: c.locals.get(name, initial)


def index_of(node: s.Element, decl: Decl, scope: Scope | None) -> Eval:
    """``name(i)`` / ``name(i, j)`` of a DIM array: its indexes compiled, one per dimension
    (``i`` for a one-dimensional array, the tuple ``(i, j)`` for two; the context checks each
    against its size at run time)."""
    want = max(len(decl.dims), 1)
    if len(node.indices) != want:
        form = ", ".join("ijk"[:want])
        raise ExprError(f"{node.name} has {want} dimension{'s' if want > 1 else ''}: it needs "
                        f"{want} index{'es' if want > 1 else ''}, {node.name}({form})")
    parts = [_num(i, scope, "an array index") for i in node.indices]
    if len(parts) == 1:
        return parts[0]
    return lambda c: tuple(p(c) for p in parts)  # type: ignore[return-value]


def _element(node: s.Element, scope: Scope | None) -> Eval:
    call = _call(node, scope) if scope is not None else None
    if call is not None:
        return call
    decl = scope.get(node.name) if scope is not None else None
    if decl is None or decl.size is None:
        raise ExprError(f"{node.name} is not an array (DIM {node.name}(n) AS ... declares one) "
                        f"nor a FUNCTION of a stored BASIC library")
    idx = index_of(node, decl, scope)
    name = node.name
    return lambda c: c.element(name, decl, idx(c))


def _string_call(node: s.Call, scope: Scope | None) -> Eval:
    kinds = arg_kinds(node.name, len(node.args))
    for arg, kind in zip(node.args, kinds, strict=True):
        if kind != "any" and kind_of(arg, scope) != kind:
            want = "string" if kind == "str" else "number"
            raise _mismatch(f"an argument of {node.name} must be a {want}")
    args = [compile_expr(a, scope) for a in node.args]
    if node.name == "STR":
        value = args[0]
        decimals = args[1] if len(args) > 1 else None
        return lambda c: c.number(value(c), int(decimals(c)) if decimals else 4)
    impl = STRING_FUNCTIONS[node.name][4]
    return lambda c: impl(*(a(c) for a in args))


def _string_binary(node: s.Binary, scope: Scope | None) -> Eval:
    lk, rk = kind_of(node.left, scope), kind_of(node.right, scope)
    if lk != rk:
        raise _mismatch(f"{node.op} between a string and a number")
    left, right = compile_expr(node.left, scope), compile_expr(node.right, scope)
    compare = {"=": lambda a, b: a == b, "<>": lambda a, b: a != b, "<": lambda a, b: a < b,
               ">": lambda a, b: a > b, "<=": lambda a, b: a <= b, ">=": lambda a, b: a >= b}
    if node.op == "+":
        return lambda c: left(c) + right(c)
    if node.op in compare:
        test = compare[node.op]
        return lambda c: TRUE if test(left(c), right(c)) else FALSE
    raise _mismatch(f"{node.op} cannot be used on strings")


def compile_expr(node: s.Expr, scope: Scope | None = None) -> Eval:
    """A closure evaluating ``node`` against a running process' context.

    The context provides ``locals`` (dict), ``vr(i)``, ``table(i)`` and
    ``param(name, axis, proc)``; see :class:`motionsim.sim.trio.run.context.Context`. ``scope``
    resolves declared names (:mod:`motionsim.sim.trio.language.scope`); a type error raises
    :class:`~motionsim.sim.trio.language.scope.ExprError`.
    """
    build = _COMPILE.get(node.__class__)
    if build is None:
        raise TypeError(f"not an expression: {node!r}")
    return build(node, scope)


#: Readers shared between the expressions that read the same thing: a constant, an untyped
#: local, a string, ``VR(i)`` / ``TABLE(i)`` / a bit / a parameter / an operator of readers
#: shared themselves. A reader holds nothing but what it reads (no state of its own), so one
#: serves every use, and a program of 1 000 lines need not make (nor the cyclic collector scan)
#: thousands of equal closures (issue 32's compile time). The key names the kind and what the
#: reader holds: its value, a local's name (a str key, every other is a tuple) or the readers
#: it applies, by identity. Bounded: emptied when it reaches :data:`_SHARED_MAX` entries.
_SHARED: dict[object, Eval] = {}
_SHARED_MAX = 4096


def _remember(key: object, reader: Eval) -> Eval:
    if len(_SHARED) >= _SHARED_MAX:
        _SHARED.clear()
    _SHARED[key] = reader
    return reader


def _c_num(node: s.Num, scope: Scope | None) -> Eval:
    v = node.value
    key = (v, math.copysign(1.0, v))  # -0.0 == 0.0 as a key: the sign is part of it
    reader = _SHARED.get(key)
    return reader if reader is not None else _remember(key, lambda c: v)


def _c_str(node: s.Str, scope: Scope | None) -> Eval:
    text = node.value
    key = ("str", text)
    reader = _SHARED.get(key)
    return reader if reader is not None else _remember(key, lambda c: text)


def _c_bit(node: s.Bit, scope: Scope | None) -> Eval:
    inner = _num(node.operand, scope, "bit access")
    bit = node.bit
    key = ("bit", inner, bit)
    reader = _SHARED.get(key)
    return reader if reader is not None else _remember(
        key, lambda c: float((int(inner(c)) >> bit) & 1))


def _c_vr(node: s.VrRef, scope: Scope | None) -> Eval:
    idx = _num(node.index, scope, "VR()")
    key = ("VR", idx)
    reader = _SHARED.get(key)
    return reader if reader is not None else _remember(key, lambda c: c.vr(idx(c)))


def _c_table(node: s.TableRef, scope: Scope | None) -> Eval:
    idx = _num(node.index, scope, "TABLE()")
    key = ("TABLE", idx)
    reader = _SHARED.get(key)
    return reader if reader is not None else _remember(key, lambda c: c.table(idx(c)))


def _c_param(node: s.Param, scope: Scope | None) -> Eval:
    name = node.name
    axis = _num(node.axis, scope, "AXIS()") if node.axis is not None else None
    proc = _num(node.proc, scope, "PROC()") if node.proc is not None else None
    key = ("param", name, axis, proc)
    reader = _SHARED.get(key)
    if reader is not None:
        return reader
    if axis is None and proc is None:
        return _remember(key, lambda c: c.param(name, None, None))
    if proc is None:
        return _remember(key, lambda c: c.param(name, axis(c), None))
    return _remember(key, lambda c: c.param(name, axis(c) if axis else None, proc(c)))


def _c_unary(node: s.Unary, scope: Scope | None) -> Eval:
    inner = _num(node.operand, scope, f"unary {node.op}")
    key = (node.op, inner)
    reader = _SHARED.get(key)
    if reader is not None:
        return reader
    if node.op == "-":
        return _remember(key, lambda c: -inner(c))
    return _remember(key, lambda c: float(~int(inner(c))))


def _c_binary(node: s.Binary, scope: Scope | None) -> Eval:
    lhs, rhs = node.left, node.right
    lc, rc = lhs.__class__, rhs.__class__
    if ((lc not in ALWAYS_NUM and kind_of(lhs, scope) == "str")
            or (rc not in ALWAYS_NUM and kind_of(rhs, scope) == "str")):
        return _string_binary(node, scope)
    left, right = _COMPILE[lc](lhs, scope), _COMPILE[rc](rhs, scope)
    op = node.op
    key = (op, left, right)
    reader = _SHARED.get(key)
    if reader is not None:
        return reader
    if op == "+":
        return _remember(key, lambda c: left(c) + right(c))
    if op == "-":
        return _remember(key, lambda c: left(c) - right(c))
    if op == "*":
        return _remember(key, lambda c: left(c) * right(c))
    fn = _BINARY[op]
    return _remember(key, lambda c: fn(left(c), right(c)))


def _c_call(node: s.Call, scope: Scope | None) -> Eval:
    if node.name in STRING_FUNCTIONS:
        return _string_call(node, scope)
    if node.name in BUS_FUNCTIONS:  # ETHERCAT(...), PEEK(...) as values (card/fieldbus.py)
        name = node.name
        bus_args = [_num(a, scope, name) for a in node.args]
        return lambda c: c.bus_call(name, tuple(a(c) for a in bus_args), False)
    impl = FUNCTIONS[node.name][1]
    args = [_num(a, scope, node.name) for a in node.args]
    if len(args) == 1:
        (a,) = args
        return lambda c: float(impl(a(c)))
    return lambda c: float(impl(*(a(c) for a in args)))


def _c_io(node: s.IoRead, scope: Scope | None) -> Eval:
    io_name = node.name
    io_args = [_num(a, scope, io_name) for a in node.args]
    return lambda c: c.io_read(io_name, [a(c) for a in io_args])


_COMPILE: dict[type, Callable[[Any, Scope | None], Eval]] = {
    s.Num: _c_num, s.Str: _c_str, s.Local: _local, s.Element: _element, s.Bit: _c_bit,
    s.VrRef: _c_vr, s.TableRef: _c_table, s.Param: _c_param, s.Unary: _c_unary,
    s.Binary: _c_binary, s.Call: _c_call, s.IoRead: _c_io,
}


__all__ = ["ALWAYS_NUM", "FALSE", "FUNCTIONS", "FUZZ", "TRUE", "compile_expr", "index_of",
           "kind_of", "truth"]
