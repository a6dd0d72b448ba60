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

try:  # imported as tools.mutation_fork (the tool's tests) or beside tools/mutate.py
    from tools import mutation_patch
except ImportError:
    import mutation_patch

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


def _die_with_parent() -> None:
    """Linux: SIGKILL this child when its parent dies (no orphan keeps running a mutant)."""
    import ctypes

    with contextlib.suppress(OSError, AttributeError):
        ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG


def _fork(body: Callable[[], int], limit_s: float, log: Path | None) -> Verdict:
    start = time.perf_counter()
    sys.stdout.flush()
    sys.stderr.flush()
    pid = os.fork()
    if pid == 0:  # the child: its own process group, output to the log, never returns
        code = 70
        try:
            _die_with_parent()
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
    ready = []
    try:
        ready, _, _ = select.select([fd], [], [], limit_s)
    finally:  # over the limit, or this process interrupted: the child's group goes too
        if not ready:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(pid, signal.SIGKILL)
        _, status = os.waitpid(pid, 0)
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


class _Serve:
    """pytest plugin of a zygote: instead of running the collected tests, answer requests —
    one JSON line each: patch the mutant's functions in a fork and run the chosen tests."""

    def __init__(self, requests: int, replies: int, module: str):
        self.requests, self.replies, self.module = requests, replies, module

    def pytest_runtestloop(self, session):
        items = {item.nodeid: item for item in session.items}
        module = sys.modules[self.module]
        requests, replies = os.fdopen(self.requests), os.fdopen(self.replies, "w")

        def answer(reply: dict) -> None:
            replies.write(json.dumps(reply) + "\n")
            replies.flush()

        answer({"ready": len(items)})
        gc.collect()
        gc.freeze()
        for line in requests:
            req = json.loads(line)

            def body(req=req) -> int:
                if not mutation_patch.apply(module, req["source"], req["patch"]):
                    return PATCH_FAILED
                chosen = [items[nodeid] for nodeid in req["order"] if nodeid in items]
                for i, item in enumerate(chosen):
                    after = chosen[i + 1] if i + 1 < len(chosen) else None
                    failed = session.testsfailed
                    item.config.hook.pytest_runtest_protocol(item=item, nextitem=after)
                    if session.testsfailed > failed and req.get("killer"):
                        Path(req["killer"]).write_text(item.nodeid)
                    if session.shouldfail or session.shouldstop:
                        break
                return 1 if session.testsfailed else 0

            verdict = _fork(body, req["limit"], None)
            answer({"code": verdict.code, "seconds": verdict.seconds})
        os._exit(0)

    pytest_runtestloop.tryfirst = True  # type: ignore[attr-defined]


PATCH_FAILED = 99  # a zygote's child could not patch the mutant in: test it the slow way


class Zygote:
    """A child that imported the unmutated package and collected the subset once; each mutant
    whose change is function code only is tested in a fork of it, the functions patched
    (``tools/mutation_patch.py``): no pytest start-up, import or collection per mutant."""

    def __init__(self, files: Sequence[str], module: str, log: Path):
        req_r, req_w = os.pipe()
        rep_r, rep_w = os.pipe()
        sys.stdout.flush()
        sys.stderr.flush()
        pid = os.fork()
        if pid == 0:
            code = 70
            try:
                os.close(req_w)
                os.close(rep_r)
                _die_with_parent()
                os.setpgid(0, 0)
                out = os.open(log, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
                os.dup2(out, 1)
                os.dup2(out, 2)
                sys.dont_write_bytecode = False
                code = _pytest(files, [_Serve(req_r, rep_w, module)])
            finally:
                os._exit(code)
        os.close(req_r)
        os.close(rep_w)
        self.pid = pid
        self._requests, self._replies = os.fdopen(req_w, "w"), os.fdopen(rep_r)
        ready = self._replies.readline()
        if not ready:
            self.close()
            raise RuntimeError(f"the zygote for {module} did not start; see {log}")

    def run(self, source: str, patch: list[str], order: Sequence[str],
            limit_s: float, killer: Path | None = None) -> Verdict:
        """Test a mutant in a fork; the id of the test that failed, if one did, is written
        to ``killer`` (the caller orders the next mutants' tests by it)."""
        self._requests.write(json.dumps({"source": source, "patch": patch,
                                         "order": list(order), "limit": limit_s,
                                         "killer": str(killer) if killer else None}) + "\n")
        self._requests.flush()
        reply = self._replies.readline()
        if not reply:
            raise RuntimeError("the zygote died")
        data = json.loads(reply)
        return Verdict(data["code"], data["seconds"])

    def close(self) -> None:
        with contextlib.suppress(OSError):
            self._requests.close()
        with contextlib.suppress(ProcessLookupError):
            os.killpg(self.pid, signal.SIGKILL)
        with contextlib.suppress(ChildProcessError):
            os.waitpid(self.pid, 0)
