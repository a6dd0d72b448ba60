"""``make run`` installs only what serving needs; ``make test`` adds the ``test`` extra. The two
have their own install stamps, so serving never pulls pytest or Dask, and the package's own
requirements (what ``pip install motionsim`` brings) hold no test or cluster tool."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from importlib.metadata import requires
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
TEST_ONLY = ("pytest", "hypothesis", "ruff", "websockets", "dask", "distributed", "pymodbus",
             "telnetlib3", "dls-pmaclib")


def _recipe(target: str) -> list[str]:
    """The commands ``make`` would run for ``target`` from scratch (``-n -B``)."""
    make = shutil.which("make")
    assert make, ".ci/run installs make"
    # run under `make test` too: the parent make's MAKEFLAGS / MAKELEVEL would make this one
    # print "make[1]: Entering directory" lines around the recipe
    env = {k: v for k, v in os.environ.items() if k not in ("MAKEFLAGS", "MAKELEVEL", "MFLAGS")}
    out = subprocess.run([make, "--no-print-directory", "-n", "-B", target], cwd=ROOT, env=env,
                         capture_output=True, text=True, check=True, timeout=30)
    return out.stdout.splitlines()


def _installs(lines: list[str]) -> list[str]:
    return [line for line in lines if re.search(r"pip install\b.*-e\b", line)]


def test_make_run_installs_the_package_without_extras():
    installs = _installs(_recipe("run"))
    assert installs, "make run installs nothing"
    assert all("[" not in line for line in installs), installs
    assert _recipe("run")[-1].endswith("motionsim serve")


def test_make_test_installs_the_test_extra():
    installs = _installs(_recipe("test"))
    assert any(".[test]" in line for line in installs), installs


def test_run_and_test_have_different_install_stamps():
    run = [line for line in _recipe("run") if line.startswith("touch")]
    test = [line for line in _recipe("test") if line.startswith("touch")]
    assert set(run) - set(test) and set(test) - set(run)


def test_serving_requirements_hold_no_test_or_cluster_tool():
    base = [r for r in requires("motionsim") or [] if "extra ==" not in r]
    names = {re.split(r"[<>=!~\[; ]", r, maxsplit=1)[0].lower() for r in base}
    assert "fastapi" in names and "uvicorn" in names and "fastapi-offline" in names
    assert not names & set(TEST_ONLY), names & set(TEST_ONLY)
