"""The layers of DESIGN.md, checked on the source: api -> app -> sim, and sim stays pure.

``sim/`` imports only simpy, the standard library (no asyncio) and itself; ``app/`` never
imports ``api/`` at module level (the protocol listeners are loaded by name, on demand).
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def _layer(module: str) -> str:
    parts = module.split(".")
    return ".".join(parts[:2]) if parts[0] == "motionsim" else parts[0]


def _imports(path: Path) -> list[tuple[str, int, bool]]:
    """(layer or top-level module, line, at module level) of every import in ``path``.

    ``motionsim.sim.pmac`` counts as ``motionsim.sim``; ``simpy`` as ``simpy``.
    """
    tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
    top_level = {id(node) for node in tree.body}
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [(_layer(a.name), node.lineno, id(node) in top_level) for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            out.append((_layer(node.module), node.lineno, id(node) in top_level))
    return out


def test_sim_imports_only_simpy_the_standard_library_and_itself():
    allowed = (set(sys.stdlib_module_names) - {"asyncio"}) | {"simpy", "motionsim.sim",
                                                               "__future__"}
    bad = [f"{p.relative_to(ROOT)}:{line} imports {mod}"
           for p in sorted((ROOT / "sim").rglob("*.py"))
           for mod, line, _ in _imports(p) if mod not in allowed]
    assert bad == []


def test_app_does_not_import_api_at_module_level():
    bad = [f"{p.relative_to(ROOT)}:{line}"
           for p in sorted((ROOT / "app").rglob("*.py"))
           for mod, line, top in _imports(p) if mod == "motionsim.api" and top]
    assert bad == []


def test_nothing_imports_the_bare_layer_names():
    """Installed, the layers exist only as ``motionsim.sim`` / ``.app`` / ``.api``: a bare
    ``import app`` would find a user's own package of that name (or nothing)."""
    trees = ("sim", "app", "api", "motionsim", "tests", "bench", "examples")
    bad = [f"{p.relative_to(ROOT)}:{line} imports {mod}"
           for tree in trees for p in sorted((ROOT / tree).rglob("*.py"))
           for mod, line, _ in _imports(p) if mod in ("sim", "app", "api")]
    assert bad == []
