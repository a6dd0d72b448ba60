"""motionsim: a discrete-event simulation service of Turbo PMAC and Trio controller buffering.

One import package with three layers (see ``docs/DESIGN.md``): :mod:`motionsim.sim` (the
simulation core), :mod:`motionsim.app` (composition, clocks, CLI) and :mod:`motionsim.api`
(REST, WebSocket and the controllers' TCP protocols). In the repository they are the top-level
folders ``sim/``, ``app/`` and ``api/``, mapped under ``motionsim`` by ``pyproject.toml``.
"""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("motionsim")
except PackageNotFoundError:  # running from a tree that was never installed
    __version__ = "0.0.0"
