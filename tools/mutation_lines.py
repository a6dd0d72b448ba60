"""Where a mutant sits in its module, read from the unmutated source with ``ast``.

Two questions ``tools/mutate.py`` asks before it runs anything:

- is the mutant *inert*: inside a type annotation (never evaluated under ``from __future__
  import annotations``) or a docstring? Then it is equivalent by construction and not run;
- which source lines must execute for the mutant to matter: the lines of the innermost
  statement holding it (the header only, for a compound statement: its body has statements of
  its own). A test that executes none of them runs exactly as on the unmutated code, so only
  the tests whose coverage touches those lines are run (``select``).
"""

from __future__ import annotations

import ast
import hashlib
from collections.abc import Iterable, Mapping

Pos = tuple[int, int]  # (line, column) as cosmic-ray records a mutant's start
Span = tuple[Pos, Pos]

IMPORT_CONTEXT = ""  # the coverage context of lines run outside any test (import, collection)


def _span(node: ast.AST) -> Span:
    return (node.lineno, node.col_offset), (node.end_lineno, node.end_col_offset)


def inert_spans(source: str) -> list[tuple[Span, str]]:
    """Spans of the source that are never evaluated as code, each with what it is:
    ``annotation`` (only when the module has ``from __future__ import annotations``) and
    ``docstring``."""
    tree = ast.parse(source)
    lazy = any(isinstance(n, ast.ImportFrom) and n.module == "__future__"
               and any(a.name == "annotations" for a in n.names) for n in tree.body)
    spans: list[tuple[Span, str]] = []
    for node in ast.walk(tree):
        if lazy:
            notes = []
            if isinstance(node, ast.arg | ast.AnnAssign) and node.annotation is not None:
                notes.append(node.annotation)
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef) and node.returns:
                notes.append(node.returns)
            spans += [(_span(n), "annotation") for n in notes]
        if isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef):
            first = node.body[0] if node.body else None
            if (isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant)
                    and isinstance(first.value.value, str)):
                spans.append((_span(first), "docstring"))
    return spans


def inert_reason(spans: Iterable[tuple[Span, str]], pos: Pos) -> str | None:
    """What inert span holds ``pos`` (``annotation`` / ``docstring``), or None."""
    for (start, end), what in spans:
        if start <= tuple(pos) <= end:
            return what
    return None


def _start_line(node: ast.AST) -> int:
    decorators = getattr(node, "decorator_list", [])
    return min([node.lineno, *(d.lineno for d in decorators)])


def _header_end(node: ast.AST) -> int:
    """Last line of a statement's own code: before its body for a compound statement."""
    body = getattr(node, "body", None)
    if isinstance(body, list) and body and isinstance(body[0], ast.AST):
        return max(node.lineno, body[0].lineno - 1)
    return node.end_lineno


class StatementIndex:
    """The statements and ``except`` handlers of one module, to find the one holding a mutant.
    (A ``match`` statement counts whole, its cases included: a superset, never too few.)"""

    def __init__(self, source: str):
        self._nodes = [n for n in ast.walk(ast.parse(source))
                       if isinstance(n, ast.stmt | ast.excepthandler)]

    def lines(self, pos: Pos) -> range:
        """Source lines that run when the code at ``pos`` runs: the header of the innermost
        statement holding ``pos`` (nested statements start after the ones holding them)."""
        line, col = pos
        holding = [n for n in self._nodes
                   if (_start_line(n), 0) <= (line, col) <= (n.end_lineno, n.end_col_offset)]
        if not holding:
            return range(line, line + 1)
        best = max(holding, key=lambda n: (_start_line(n), n.lineno, n.col_offset))
        return range(_start_line(best), max(_header_end(best), line) + 1)


def select(contexts_by_line: Mapping[int, Iterable[str]], lines: Iterable[int]) -> set[str] | None:
    """The tests (coverage contexts) that execute any of ``lines``; None when one of them runs
    at import time (a module-level line: every test depends on it, so the whole subset runs).
    An empty set means no test executes the mutant: it survives without running."""
    tests: set[str] = set()
    for line in lines:
        for context in contexts_by_line.get(line, ()):
            if context == IMPORT_CONTEXT:
                return None
            tests.add(context)
    return tests


class FunctionAnchors:
    """The innermost function or method holding a line: its qualified name, a digest of its
    code (its ``ast`` dump: comments, blank lines and its place in the file do not count) and
    its first line. A mutant's result carries over to a new version of the module when its
    function's code is the same there (``tools/mutate.py``)."""

    def __init__(self, source: str) -> None:
        self._defs: list[tuple[int, int, str, str]] = []  # start, end, qualname, digest

        def walk(node: ast.AST, prefix: str) -> None:
            for child in ast.iter_child_nodes(node):
                if isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
                    name = prefix + child.name
                    if not isinstance(child, ast.ClassDef):
                        start = min([d.lineno for d in child.decorator_list] + [child.lineno])
                        code = ast.dump(child).encode()
                        digest = hashlib.sha256(code).hexdigest()[:16]
                        self._defs.append((start, child.end_lineno, name, digest))
                    walk(child, name + ".")
                else:
                    walk(child, prefix)

        walk(ast.parse(source), "")

    def anchor(self, line: int) -> tuple[str, str] | None:
        """``(qualname, digest)`` of the innermost function holding ``line``, or None (module
        or class level: code run at import, which every function depends on)."""
        best = None
        for start, end, name, digest in self._defs:
            if start <= line <= end and (best is None or start >= best[0]):
                best = (start, name, digest)
        return None if best is None else (best[1], best[2])
