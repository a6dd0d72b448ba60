"""The parts of sim/trio and their import order, checked on the source (DESIGN.md "sim/trio").

``card`` imports nothing else of sim/trio; ``language`` only ``card``; ``motion`` ``card`` and
``language``; ``run`` those three; ``terminal`` and ``controller`` (and the package's
``__init__``) sit on top. An import against that order fails, wherever it is written (a late
import inside a function too; ``if TYPE_CHECKING:`` imports are for annotations only and do
not count), and so does any cycle of module-level imports between two modules of sim/trio.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from tests.import_names import module_of

ROOT = Path(__file__).resolve().parents[2]
TRIO = ROOT / "sim" / "trio"
PACKAGE = "motionsim.sim.trio"

#: The parts, lowest first: each may import its own part and the ones before it.
ORDER = ("card", "language", "motion", "run", "")  # "" = the top: controller, terminal


def _name(path: Path) -> str:
    rel = path.relative_to(TRIO).with_suffix("")
    parts = [p for p in rel.parts if p != "__init__"]
    return ".".join(parts)


MODULES = {_name(p): p for p in sorted(TRIO.rglob("*.py"))}


def _part(module: str) -> str:
    head = module.split(".")[0]
    return head if head in ORDER[:-1] else ""


def _type_checking(node: ast.AST) -> bool:
    return isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test)


def _targets(node: ast.Import | ast.ImportFrom, path: Path) -> list[str]:
    """The sim/trio modules an import statement loads (a name imported from a package is the
    submodule of that name when there is one, else the package itself)."""
    if isinstance(node, ast.Import):
        names = [a.name for a in node.names]
    elif mod := module_of(path, node, ROOT):
        names = [f"{mod}.{a.name}" if f"{mod}.{a.name}"[len(PACKAGE) + 1:]
                 in MODULES else mod for a in node.names]
    else:
        return []
    return [n[len(PACKAGE) + 1:] for n in names if n.startswith(PACKAGE + ".")]


def imports(path: Path) -> list[tuple[str, int, bool]]:
    """(sim/trio module, line, at module level) of every import in ``path`` that is not
    under ``if TYPE_CHECKING:``."""
    tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
    out: list[tuple[str, int, bool]] = []

    def walk(node: ast.AST, top: bool) -> None:
        for child in ast.iter_child_nodes(node):
            if _type_checking(child):
                continue
            if isinstance(child, ast.Import | ast.ImportFrom):
                out.extend((t, child.lineno, top) for t in _targets(child, path))
            nested = isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef
                                | ast.Lambda)
            walk(child, top and not nested)

    walk(tree, True)
    return out


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Every cycle of ``graph`` found by a depth-first walk (each reported once, from the
    module where the walk closed it)."""
    found: list[list[str]] = []
    state: dict[str, int] = {}  # 1 = on the current path, 2 = done
    path: list[str] = []

    def visit(node: str) -> None:
        state[node] = 1
        path.append(node)
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == 1:
                found.append(path[path.index(nxt):] + [nxt])
            elif nxt not in state:
                visit(nxt)
        path.pop()
        state[node] = 2

    for node in sorted(graph):
        if node not in state:
            visit(node)
    return found


def test_every_module_of_sim_trio_is_in_a_part_or_on_top():
    tops = sorted(m for m in MODULES if _part(m) == "" and m not in ORDER)
    assert tops == ["controller", "terminal"]
    assert {_part(m) for m in MODULES} == set(ORDER)


def test_each_part_imports_only_the_parts_before_it():
    bad = [f"sim/trio/{MODULES[m].relative_to(TRIO)}:{line} ({_part(m) or 'top'}) imports "
           f"{target} ({_part(target) or 'top'})"
           for m in MODULES if m  # the package __init__ re-exports everything
           for target, line, _top in imports(MODULES[m])
           if ORDER.index(_part(target)) > ORDER.index(_part(m))]
    assert bad == []


def test_no_module_level_import_cycle_in_sim_trio():
    graph = {m: {t for t, _line, top in imports(p) if top and t != m} for m, p in MODULES.items()}
    assert cycles(graph) == []


@pytest.mark.parametrize("graph, cycle", [
    ({"a": {"b"}, "b": {"a"}}, ["a", "b", "a"]),
    ({"a": {"b"}, "b": {"c"}, "c": {"b"}}, ["b", "c", "b"]),
])
def test_the_cycle_check_finds_a_cycle(graph, cycle):
    assert cycles(graph) == [cycle]


def test_the_import_reader_sees_module_level_late_and_type_only_imports(tmp_path):
    src = tmp_path / "m.py"
    src.write_text(
        "from typing import TYPE_CHECKING\n"
        f"from {PACKAGE}.language import statements as s\n"
        f"from {PACKAGE}.card.models import DEFAULT_MODEL\n"
        "if TYPE_CHECKING:\n"
        f"    from {PACKAGE}.controller import TrioController\n"
        "def f():\n"
        f"    from {PACKAGE}.run.context import Context\n")
    assert imports(src) == [("language.statements", 2, True), ("card.models", 3, True),
                            ("run.context", 7, False)]
