"""String values of MC4 Trio BASIC: the string functions and what a STRING local holds.

MC4xx / MC6xx firmware 2.x has string variables (``DIM s AS STRING(n)``) and string functions;
their manual pages were not reachable (spec §11.4, §11.12), so the forms below are the usual
ones of the family ``[BK]`` and the details marked ``[INF]`` are this simulator's choice:

* positions count from 1 (``MID("ABCD", 2, 2)`` = ``"BC"``, ``INSTR("ABCD", "C")`` = 3, 0 when
  not found) ``[INF]``;
* ``STR(x[, decimals])`` writes the number as PRINT does (four decimals by default) ``[INF]``;
* ``VAL(s)`` reads the leading number of ``s``, 0 when there is none ``[INF]``;
* a STRING(n) local keeps at most ``n`` characters (default 32 ``[INF]``).

Each entry: name -> (fewest, most arguments, argument kinds, result kind, implementation);
kinds are ``"num"`` or ``"str"``. STR needs the model's number format, so the context passes
it as ``fmt``.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import Any

from ..card.basic_errors import BasicError

#: Characters a STRING local holds when DIM gives no length ``[INF]``.
DEFAULT_LENGTH = 32

_NUMBER = re.compile(r"\s*[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


def _mid(s: str, start: float, length: float | None = None) -> str:
    i = max(int(start), 1) - 1
    return s[i:] if length is None else s[i : i + max(int(length), 0)]


def _instr(*args: Any) -> float:
    start, s, find = (args[0], args[1], args[2]) if len(args) == 3 else (1, args[0], args[1])
    return float(s.find(find, max(int(start), 1) - 1) + 1)


def _val(s: str) -> float:
    m = _NUMBER.match(s)
    return float(m.group()) if m else 0.0


def _chr(n: float) -> str:
    code = int(n)
    if not 0 <= code <= 255:
        raise BasicError(f"Parameter out of range: CHR({n:g})")
    return chr(code)


StringFunction = tuple[int, int, tuple[str, ...], str, Callable[..., Any]]

STRING_FUNCTIONS: dict[str, StringFunction] = {
    "LEN": (1, 1, ("str",), "num", lambda s: float(len(s))),
    "LEFT": (2, 2, ("str", "num"), "str", lambda s, n: s[: max(int(n), 0)]),
    "RIGHT": (2, 2, ("str", "num"), "str", lambda s, n: s[len(s) - int(n):] if int(n) > 0 else ""),
    "MID": (2, 3, ("str", "num", "num"), "str", _mid),
    "INSTR": (2, 3, ("any", "str", "str"), "num", _instr),
    "VAL": (1, 1, ("str",), "num", _val),
    "UCASE": (1, 1, ("str",), "str", str.upper),
    "LCASE": (1, 1, ("str",), "str", str.lower),
    "CHR": (1, 1, ("num",), "str", _chr),
    "STR": (1, 2, ("num", "num"), "str", None),  # formatted by the context (model's word)
}


def arg_kinds(name: str, n: int) -> tuple[str, ...]:
    """The kinds of ``n`` arguments of string function ``name`` (INSTR's start is optional)."""
    kinds = STRING_FUNCTIONS[name][2]
    if name == "INSTR":
        return ("num", "str", "str") if n == 3 else ("str", "str")
    return kinds[:n]


__all__ = ["DEFAULT_LENGTH", "STRING_FUNCTIONS", "arg_kinds"]
