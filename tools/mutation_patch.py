"""Code patching for ``make mutate``: a mutant that changes only function bodies is applied to
the live, already imported module by swapping those functions' ``__code__``.

This is what lets one process collect the test subset once and test many mutants: each
mutant runs in a fork of it with the changed functions patched (``tools/mutation_fork.py``).
It is used only when it is exact — the mutant changes no module or class body code (defaults,
decorators, class attributes: evaluated at import), its statement is never executed at
import or collection (``tools/mutation_lines.select`` says so), and every changed function is
found once, by qualified name, among the module's live functions. Anything else is tested
the slow way, with a fresh import of the mutated source.
"""

from __future__ import annotations

import functools
import inspect
import types
from collections import Counter

_BODY = inspect.CO_OPTIMIZED  # set for function code, clear for module and class bodies


def _codes(code: types.CodeType) -> list[types.CodeType]:
    out = [code]
    for const in code.co_consts:
        if isinstance(const, types.CodeType):
            out += _codes(const)
    return out


def _shallow(code: types.CodeType) -> tuple:
    """A body's own code, its nested functions named, not compared."""
    consts = tuple(("code", c.co_qualname) if isinstance(c, types.CodeType) else (type(c), c)
                   for c in code.co_consts)
    return code.co_code, consts, code.co_names, code.co_varnames


def changed_functions(original: str, mutated: str, filename: str) -> list[str] | None:
    """Qualified names of the functions a mutant changes, or None when it changes code that
    runs at import (a module or class body) or the functions cannot be told apart by name."""
    old = _codes(compile(original, filename, "exec", dont_inherit=True))
    new = _codes(compile(mutated, filename, "exec", dont_inherit=True))
    if [c.co_qualname for c in old] != [c.co_qualname for c in new]:
        return None
    counts = Counter(c.co_qualname for c in new)
    changed: set[str] = set()
    for a, b in zip(old, new, strict=True):
        if a == b:
            continue
        name = b.co_qualname
        if not b.co_flags & _BODY:
            if _shallow(a) != _shallow(b):
                return None
            continue
        top = name.split(".<locals>.")[0]
        if counts[top] != 1 or top.startswith("<") or ".<" in top:
            return None  # two functions of one name, or a lambda / comprehension at module level
        changed.add(top)
    return sorted(changed)


def live_functions(module: types.ModuleType) -> dict[str, list[types.FunctionType]]:
    """The module's own functions and methods (through static/class methods, properties,
    cached properties and ``__wrapped__``), by qualified name."""
    out: dict[str, list[types.FunctionType]] = {}
    seen: set[int] = set()

    def visit(obj) -> None:
        if id(obj) in seen:
            return
        seen.add(id(obj))
        if isinstance(obj, staticmethod | classmethod):
            visit(obj.__func__)
        elif isinstance(obj, property):
            for f in (obj.fget, obj.fset, obj.fdel):
                if f is not None:
                    visit(f)
        elif isinstance(obj, functools.cached_property):
            visit(obj.func)
        elif isinstance(obj, types.FunctionType):
            if obj.__module__ == module.__name__:
                out.setdefault(obj.__qualname__, []).append(obj)
            if hasattr(obj, "__wrapped__"):
                visit(obj.__wrapped__)
        elif isinstance(obj, type):
            if obj.__module__ == module.__name__:
                for value in list(vars(obj).values()):
                    visit(value)
        elif hasattr(obj, "__wrapped__"):
            visit(obj.__wrapped__)

    for value in list(vars(module).values()):
        visit(value)
    return out


def apply(module: types.ModuleType, mutated: str, names: list[str]) -> bool:
    """Swap the ``__code__`` of the functions ``names`` for the mutant's; False (nothing
    changed) when one of them is not found exactly once."""
    codes = {c.co_qualname: c for c in _codes(compile(mutated, module.__file__, "exec",
                                                       dont_inherit=True))}
    live = live_functions(module)
    targets = [live.get(name, []) for name in names]
    if any(len(found) != 1 for found in targets) or any(n not in codes for n in names):
        return False
    for (function,), name in zip(targets, names, strict=True):
        if len(function.__code__.co_freevars) != len(codes[name].co_freevars):
            return False
    for (function,), name in zip(targets, names, strict=True):
        function.__code__ = codes[name]
    return True
