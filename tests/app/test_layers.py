"""The layers of DESIGN.md, checked on the source: api -> app -> sim, and sim stays pure.

``sim/`` imports only simpy, the standard library (no asyncio) and itself; ``app/`` never
imports ``api/`` at module level (the protocol listeners are loaded by name, on demand).
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path

import pytest

from tests.import_names import module_of

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
        elif isinstance(node, ast.ImportFrom) and (mod := module_of(path, node, ROOT)):
            out.append((_layer(mod), node.lineno, id(node) in top_level))
    return out


def test_sim_imports_only_simpy_the_standard_library_and_itself():
    """Besides SimPy, the core may use numpy (a declared dependency) for array arithmetic:
    a gather buffer's samples are computed on read as arrays (sim/pmac/tasks/gather_readers)."""
    allowed = (set(sys.stdlib_module_names) - {"asyncio"}) | {"simpy", "numpy", "motionsim.sim",
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


# -- the PMAC sub-packages (docs/DESIGN.md "The simulation core") ---------------------------

#: The order DESIGN.md states, lowest first: a sub-package imports only those of a lower
#: tier, or of its own tier without a cycle. ``kinematics`` (compiled once, run per move)
#: sits with the lookahead it serves.
PMAC_TIERS = (
    ("language", "card"),
    ("buffers", "motor", "tasks"),
    ("lookahead", "modes", "kinematics"),
    ("host", "controller", "__init__"),
)
_TIER = {name: i for i, names in enumerate(PMAC_TIERS) for name in names}
_PMAC = ROOT / "sim" / "pmac"


def _part(path: Path) -> str:
    rel = path.relative_to(_PMAC)
    return rel.parts[0] if len(rel.parts) > 1 else rel.stem


def _pmac_imports(path: Path) -> list[tuple[str, int, bool]]:
    """(sub-package, line, at module level) of every run-time import of another PMAC
    sub-package in ``path``; imports under ``if TYPE_CHECKING:`` are for annotations only."""
    tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
    typing_only = {id(n) for top in tree.body if isinstance(top, ast.If)
                   and "TYPE_CHECKING" in ast.unparse(top.test) for n in ast.walk(top)}
    top_level = {id(node) for node in tree.body}
    out = []
    for node in ast.walk(tree):
        if id(node) in typing_only:
            continue
        if isinstance(node, ast.ImportFrom) and (mod := module_of(path, node, ROOT)):
            names = [mod] + [f"{mod}.{a.name}" for a in node.names]
        elif isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        else:
            continue
        for name in names:
            parts = name.split(".")
            if parts[:3] == ["motionsim", "sim", "pmac"] and len(parts) > 3 and parts[3] in _TIER:
                out.append((parts[3], node.lineno, id(node) in top_level))
                break
    return out


def _pmac_edges() -> dict[tuple[str, str], list[str]]:
    edges: dict[tuple[str, str], list[str]] = {}
    for p in sorted(_PMAC.rglob("*.py")):
        src = _part(p)
        for dst, line, top in _pmac_imports(p):
            if dst != src:
                where = f"{p.relative_to(ROOT)}:{line}" + ("" if top else " (inside a function)")
                edges.setdefault((src, dst), []).append(where)
    return edges


def test_every_pmac_module_is_in_a_tier():
    parts = {_part(p) for p in _PMAC.rglob("*.py")}
    assert parts - set(_TIER) == set()


def test_pmac_sub_packages_import_only_down_the_order():
    """``language`` and ``card`` depend on nothing else of the PMAC; ``buffers``, ``motor``,
    ``tasks`` on those; ``lookahead`` / ``modes`` / ``kinematics`` on those; ``host`` and
    ``controller`` on everything. A late import inside a function counts too: it hides the
    same dependency."""
    bad = [f"{src} -> {dst}: {where}" for (src, dst), wheres in sorted(_pmac_edges().items())
           if _TIER[dst] > _TIER[src] for where in wheres]
    assert bad == []


def test_pmac_sub_packages_have_no_import_cycle():
    graph: dict[str, set[str]] = {}
    for src, dst in _pmac_edges():
        graph.setdefault(src, set()).add(dst)
    cycles = []
    for start in sorted(graph):
        stack = [(start, [start])]
        while stack:
            node, path = stack.pop()
            for nxt in sorted(graph.get(node, ())):
                if nxt == start:
                    cycles.append(" -> ".join([*path, start]))
                elif nxt not in path:
                    stack.append((nxt, [*path, nxt]))
    assert cycles == []


def _fake_pmac(tmp_path, monkeypatch, language: str, buffers: str) -> None:
    """A source tree whose ``language`` and ``buffers`` hold one module of the given text."""
    fake = tmp_path / "sim" / "pmac"
    for part, text in (("language", language), ("buffers", buffers)):
        (fake / part).mkdir(parents=True)
        (fake / part / "m.py").write_text(text)
    monkeypatch.setattr(sys.modules[__name__], "_PMAC", fake)
    monkeypatch.setattr(sys.modules[__name__], "ROOT", tmp_path)


@pytest.mark.parametrize(("language", "buffers"), [
    ("from motionsim.sim.pmac.buffers import program\n",
     "from motionsim.sim.pmac.language import parser\n"),
    ("from ..buffers import program\n", "from ..language import parser\n"),
], ids=["absolute", "relative"])
def test_the_layer_checks_see_a_cycle(tmp_path, monkeypatch, language, buffers):
    """The checks above fail on a module-level cycle (a language module importing buffers,
    which imports the language), written with absolute or relative imports."""
    _fake_pmac(tmp_path, monkeypatch, language, buffers)
    with pytest.raises(AssertionError):
        test_pmac_sub_packages_have_no_import_cycle()
    with pytest.raises(AssertionError):
        test_pmac_sub_packages_import_only_down_the_order()


#: What ``api/`` may import of ``sim/``: the shared modules directly in ``sim/`` (errors,
#: events, bounds, the controller base...) and the controller kinds' packages themselves.
def _public(module: str) -> bool:
    parts = module.split(".")
    if parts[:2] != ["motionsim", "sim"]:
        return True
    if len(parts) == 3:
        return (ROOT / "sim" / f"{parts[2]}.py").exists() or parts[2] in ("pmac", "trio")
    return len(parts) == 2


def test_api_imports_only_the_controllers_public_surface():
    bad = []
    for p in sorted((ROOT / "api").rglob("*.py")):
        tree = ast.parse(p.read_text(encoding="utf-8"), str(p))
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and (mod := module_of(p, node, ROOT)):
                mods = [mod]
            elif isinstance(node, ast.Import):
                mods = [a.name for a in node.names]
            else:
                continue
            bad += [f"{p.relative_to(ROOT)}:{node.lineno} imports {m}" for m in mods
                    if not _public(m)]
    assert bad == []


def test_the_package_imports_itself_by_relative_names():
    """Issue 31 item 4: inside sim/, app/ and api/ every import of the package is relative,
    so the layers connect in the source tree alone (an IDE or a structure tool without the
    editable install); and the checks above read those imports (the PMAC graph is not empty)."""
    bad = []
    for tree in ("sim", "app", "api"):
        for p in sorted((ROOT / tree).rglob("*.py")):
            for node in ast.walk(ast.parse(p.read_text(encoding="utf-8"), str(p))):
                if isinstance(node, ast.ImportFrom) and node.level == 0 and (
                        node.module or "").split(".")[:2] in (["motionsim", t] for t in
                                                              ("sim", "app", "api")):
                    bad.append(f"{p.relative_to(ROOT)}:{node.lineno} from {node.module}")
                elif isinstance(node, ast.Import):
                    bad += [f"{p.relative_to(ROOT)}:{node.lineno} import {a.name}"
                            for a in node.names if a.name.startswith("motionsim.")]
    assert bad == []
    edges = _pmac_edges()
    assert ("host", "language") in edges and ("controller", "lookahead") in edges


def test_no_command_line_imports_the_bare_layer_names():
    """A ``python -c "from app.cli import main"`` run from the source tree imports ``app`` as
    a top-level package, whose relative imports then reach beyond it: commands run
    ``python -m motionsim`` (or the ``motionsim`` script)."""
    import re

    bare = re.compile(r"""["']\s*(?:from|import)\s+(?:app|sim|api)\b""")
    bad = [f"{p.relative_to(ROOT)}:{n}" for tree in ("tests", "bench", "tools", "examples")
           for p in sorted((ROOT / tree).rglob("*.py")) if p != Path(__file__).resolve()
           for n, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1)
           if bare.search(line) and "user's own" not in line]
    assert bad == []
