"""What a name in a program stands for when it is compiled: a local, a typed local, an array, a
VR named by GLOBAL, or a named CONSTANT.

The controller compiles a program before it runs it (TJ1P-31); MC4 declarations are resolved
then (spec §11.2, §11.4):

* ``DIM name[(n)] AS type`` declares a typed local (or an array of ``n``, indexed from 0) of
  this program from that line on; a second DIM of the name, or a DIM after the name was used
  as a plain local, is a compile error (``[BK]``: DIM comes before the first use);
* ``GLOBAL "name", vr`` and ``CONSTANT "name", v`` name a VR / a value for this program from
  that line on, and — once the statement has run — for every program compiled afterwards
  (``[BK]``: the MC4 help recommends declaring them in the STARTUP program);
* any other name is an untyped local (a float, 0 until written).

Values of typed locals ``[INF]`` (spec §11.4): INTEGER truncates toward zero on assignment,
BOOLEAN holds TRUE (-1) or FALSE (0), FLOAT is the model's word, STRING holds text (at most
its length).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from .strings import DEFAULT_LENGTH


class ExprError(Exception):
    """A compile error inside an expression (type mismatch, undeclared array ...); the compiler
    gives it the statement's line and column."""


@dataclass(frozen=True, slots=True)
class Decl:
    """A declared name: ``kind`` is ``DIM``, ``GLOBAL`` or ``CONSTANT``."""

    kind: str
    type: str = "FLOAT"  # DIM: INTEGER, FLOAT, STRING, BOOLEAN
    size: int | None = None  # DIM: array size (elements in all)
    length: int = DEFAULT_LENGTH  # DIM STRING: characters kept
    index: int = 0  # GLOBAL: the VR
    value: float = 0.0  # CONSTANT
    dims: tuple[int, ...] = ()  # DIM: the array's shape, (n,) or (n, m)

    @property
    def is_str(self) -> bool:
        return self.kind == "DIM" and self.type == "STRING"

    def initial(self) -> float | str:
        """What the local holds after its DIM (0, FALSE or the empty string)."""
        return "" if self.is_str else 0.0


class Scope:
    """The names a program's expressions are compiled against."""

    def __init__(self, shared: Mapping[str, Decl] | None = None,
                 functions: Mapping[str, Any] | None = None) -> None:
        self.names: dict[str, Decl] = dict(shared or {})
        self.untyped: set[str] = set()  # names used so far as plain locals (DIM must precede)
        #: The library functions a program can call (:mod:`.functions`), by name.
        self.functions: Mapping[str, Any] = functions or {}
        #: The libraries whose functions the program calls.
        self.used: set[str] = set()
        #: Library function calls compiled so far (the compiler marks their statements).
        self.calls = 0

    def function(self, name: str) -> Any:
        """The library function ``name`` stands for (None: a variable, declared or not)."""
        if name in self.names:
            return None
        return self.functions.get(name)

    def get(self, name: str) -> Decl | None:
        return self.names.get(name)

    def plain(self, name: str) -> Decl | None:
        """The declaration of ``name``; None — and the name noted as an untyped local — if
        there is none."""
        decl = self.names.get(name)
        if decl is None:
            self.untyped.add(name)
        return decl


def rebinding(name: str, old: Decl | None, new: Decl) -> str | None:
    """Why ``new`` (a GLOBAL or CONSTANT of ``name``) may not replace ``old``, or None.

    A GLOBAL / CONSTANT name is one binding for every program of the controller ``[BK]`` (the
    MC4 help gives no rule; refusing is the choice that cannot silently redirect another
    program's ``name``): declaring it again the same way is fine (a start-up program run
    twice), a GLOBAL naming another VR, a CONSTANT of another value, or a CONSTANT over a
    GLOBAL (and the reverse) is refused with both bindings named."""
    if old is None or old.kind not in ("GLOBAL", "CONSTANT") or old == new:
        return None

    def said(d: Decl) -> str:
        return f"GLOBAL VR({d.index})" if d.kind == "GLOBAL" else f"CONSTANT {d.value:g}"

    return (f"{new.kind} {name!r}: {name} is already {said(old)}; a shared name cannot be "
            f"declared again as {said(new)}")


def coerce(decl: Decl | None, value: float | str) -> float | str:
    """A value as a typed local stores it (untyped: unchanged)."""
    if decl is None or decl.kind != "DIM":
        return value
    if decl.type == "INTEGER":
        return float(int(value))  # type: ignore[arg-type]
    if decl.type == "BOOLEAN":
        return -1.0 if value != 0.0 else 0.0
    if decl.type == "STRING":
        return str(value)[: decl.length]
    return value


__all__ = ["Decl", "ExprError", "Scope", "coerce", "rebinding"]
