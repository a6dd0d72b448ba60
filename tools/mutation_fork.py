"""The warm fork server of ``make mutate``: each mutant is tested in a forked child.

The parent imports the third-party stack once (pytest and its plugins, FastAPI, pydantic,
httpx, SimPy, hypothesis, coverage) and never the package under test. For a mutant it forks a
child that puts the mutated source of ONE module in front of the import system (a meta-path
finder serving that module from memory: the file on disk is never changed, so a crash cannot
leave a mutant behind and the work tree stays usable during a run), then runs ``pytest.main``
in-process on the chosen tests, fastest first, stopping at the first failure. The child's exit
code is the verdict; a child over its time limit is killed with its process group.

Test subprocesses (none in today's subsets) would import the unmutated files from disk.
"""

from __future__ import annotations

import contextlib
import gc
import importlib.abc
import importlib.util
import json
import os
import select
import signal
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

PRELOAD = ("pytest", "_pytest.pytester", "pytest_timeout", "anyio", "anyio.pytest_plugin",
           "hypothesis", "hypothesis.extra.pytestplugin", "fastapi", "fastapi.testclient",
           "starlette", "pydantic", "pydantic_settings", "httpx", "simpy", "uvicorn",
           "websockets", "yaml", "coverage")
PYTEST_ARGS = ("-x", "-q", "-p", "no:cacheprovider", "-p", "no:randomly",
               "--hypothesis-seed=0", "-W", "ignore")


def preload(package: str) -> None:
    """Import the third-party stack the tests use, so every child starts warm. Refuses to run
    with ``package`` (the code under test) already imported: a child would inherit it
    unmutated."""
    import importlib
    import importlib.metadata

    for name in PRELOAD:
        with contextlib.suppress(ImportError):
            importlib.import_module(name)
    for plugin in importlib.metadata.entry_points(group="pytest11"):  # pytest's plugins
        if not plugin.value.startswith(package):
            with contextlib.suppress(Exception):  # one failing here fails in the child too
                plugin.load()
    loaded = sorted(m for m in sys.modules if m == package or m.startswith(package + "."))
    if loaded:
        raise RuntimeError(f"{package} imported before forking: {', '.join(loaded[:5])}")
    gc.collect()
    gc.freeze()  # the children's collections (pytest runs several) skip the preloaded objects


class _FromMemory(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Serves module ``name`` from ``source`` (compiled as if it were ``path``)."""

    def __init__(self, name: str, path: Path, source: str):
        self.name, self.path, self.source = name, path, source

    def find_spec(self, fullname, path=None, target=None):
        if fullname != self.name:
            return None
        return importlib.util.spec_from_file_location(fullname, self.path, loader=self)

    def create_module(self, spec):
        return None

    def exec_module(self, module) -> None:
        exec(compile(self.source, str(self.path), "exec", dont_inherit=True), module.__dict__)


class _Choose:
    """pytest plugin: keep only the chosen test ids, in the given order."""

    def __init__(self, order: Sequence[str] | None):
        self.rank = None if order is None else {nodeid: i for i, nodeid in enumerate(order)}

    def pytest_collection_modifyitems(self, config, items) -> None:
        if self.rank is None:
            return
        kept = sorted((i for i in items if i.nodeid in self.rank),
                      key=lambda i: self.rank[i.nodeid])
        dropped = [i for i in items if i.nodeid not in self.rank]
        if dropped:
            config.hook.pytest_deselected(items=dropped)
        items[:] = kept


class _Contexts:
    """pytest plugin: one coverage context per test (its node id) and each test's duration."""

    def __init__(self, cov):
        self.cov, self.durations = cov, {}

    def pytest_runtest_protocol(self, item, nextitem):
        self.cov.switch_context(item.nodeid)
        start = time.perf_counter()
        yield
        self.durations[item.nodeid] = time.perf_counter() - start
        self.cov.switch_context("")

    pytest_runtest_protocol.hookwrapper = True  # type: ignore[attr-defined]


@dataclass
class Verdict:
    code: int | None  # pytest's exit code; None when the time limit killed the child
    seconds: float

    @property
    def timed_out(self) -> bool:
        return self.code is None


def _fork(body: Callable[[], int], limit_s: float, log: Path | None) -> Verdict:
    start = time.perf_counter()
    sys.stdout.flush()
    sys.stderr.flush()
    pid = os.fork()
    if pid == 0:  # the child: its own process group, output to the log, never returns
        code = 70
        try:
            os.setpgid(0, 0)
            out = os.open(log or os.devnull, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
            os.dup2(out, 1)
            os.dup2(out, 2)
            sys.dont_write_bytecode = False  # only unmutated files are ever compiled from disk
            code = body()
        except BaseException:  # noqa: BLE001 - any failure is the verdict, never a return
            import traceback

            traceback.print_exc()
        finally:
            sys.stdout.flush()
            sys.stderr.flush()
            os._exit(code)
    fd = os.pidfd_open(pid)
    try:
        ready, _, _ = select.select([fd], [], [], limit_s)
        if not ready:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(pid, signal.SIGKILL)
        _, status = os.waitpid(pid, 0)
    finally:
        os.close(fd)
    code = os.waitstatus_to_exitcode(status) if ready else None
    return Verdict(code, time.perf_counter() - start)


def _pytest(files: Sequence[str], plugins: list) -> int:
    import pytest

    return int(pytest.main([*PYTEST_ARGS, *files], plugins=plugins))


def baseline(files: Sequence[str], target: Path, out: Path, limit_s: float,
             log: Path) -> Verdict:
    """Run the subset once on the unmutated code under coverage with a context per test;
    write ``{"lines": {line: [test ids]}, "durations": {test id: s}}`` for ``target`` to
    ``out``. Lines run outside any test (module import) carry the context ``""``."""

    def body() -> int:
        import coverage

        cov = coverage.Coverage(data_file=None, include=[str(target)], config_file=False)
        contexts = _Contexts(cov)
        cov.start()
        try:
            code = _pytest(files, [contexts])
        finally:
            cov.stop()
        data = cov.get_data()
        measured = data.measured_files()
        lines = data.contexts_by_lineno(measured.pop()) if measured else {}
        out.write_text(json.dumps({"lines": lines, "durations": contexts.durations}))
        return code

    return _fork(body, limit_s, log)


def run_mutant(files: Sequence[str], order: Sequence[str] | None, module: str, target: Path,
               source: str, limit_s: float) -> Verdict:
    """Test one mutant: ``module`` (at ``target``) imported from ``source``, the tests
    ``order`` (None: all of ``files``) run first-to-last, stopping at the first failure."""

    def body() -> int:
        sys.meta_path.insert(0, _FromMemory(module, target, source))
        return _pytest(files, [_Choose(order)])

    return _fork(body, limit_s, None)
