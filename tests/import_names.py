"""Absolute module names for the import statements of the package's source files.

Inside ``sim/``, ``app/`` and ``api/`` imports are relative (``from ..buffers import flow``), so
that a reader's tools resolve them from the source tree alone. The structure tests read those
statements with :func:`module_of`, which turns either form into the installed name
(``motionsim.sim.pmac.buffers``) through the package-dir map of ``pyproject.toml``.
"""

from __future__ import annotations

import ast
from pathlib import Path

#: pyproject.toml [tool.setuptools.package-dir]: source folder -> installed package.
PACKAGE_DIRS = {"sim": "motionsim.sim", "app": "motionsim.app", "api": "motionsim.api",
                "motionsim": "motionsim"}


def package_of(path: Path, root: Path) -> str:
    """The installed package a source file belongs to (its own name for an ``__init__``)."""
    rel = path.relative_to(root)
    base = PACKAGE_DIRS.get(rel.parts[0], rel.parts[0])
    return ".".join([base, *rel.parts[1:-1]])


def module_of(path: Path, node: ast.ImportFrom, root: Path) -> str | None:
    """The absolute module ``node`` imports from (``None`` for a level that leaves the
    package)."""
    if node.level == 0:
        return node.module
    parts = package_of(path, root).split(".")
    if node.level - 1 >= len(parts):
        return None
    base = parts[: len(parts) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))
