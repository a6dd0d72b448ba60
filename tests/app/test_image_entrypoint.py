"""The container image's command, run as its unprivileged user in a fresh working directory
(no Docker engine here): it serves, its health check follows the configured port, and
``motionsim serve --record`` and ``motionsim run --out`` can write where it runs.

The Dockerfile is read for what the image does (``ENV MOTIONSIM_*``, ``CMD``, the ``chown`` of
its ``WORKDIR``); the test mirrors it with a temporary directory owned by an unprivileged uid
and ``setpriv`` (CI runs as root; a developer who is not root already is unprivileged). The
user keeps only the right to read files anywhere (the checkout may sit in a root-only folder);
writing still needs what the image gives it."""

from __future__ import annotations

import contextlib
import json
import os
import posixpath
import re
import shlex
import shutil
import socket
import struct
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
import yaml

from tests.processes import stop

ROOT = Path(__file__).resolve().parents[2]
BIN = Path(sys.executable).parent
DOCKERFILE = (ROOT / "Dockerfile").read_text()
UID = 10001  # the image's `useradd --uid`


def _instructions(name: str) -> list[str]:
    """The arguments of every ``name`` instruction (continuation lines joined)."""
    text = re.sub(r"\\\n\s*", " ", DOCKERFILE)
    return [m.group(1).strip() for m in re.finditer(rf"^{name}\s+(.*)$", text, re.M)]


def image_env() -> dict[str, str]:
    env: dict[str, str] = {}
    for args in _instructions("ENV"):
        for item in shlex.split(args):
            key, _, value = item.partition("=")
            env[key] = value
    return env


def image_cmd() -> list[str]:
    (cmd,) = _instructions("CMD")
    return json.loads(cmd)


def image_healthcheck() -> list[str]:
    """The ``HEALTHCHECK ... CMD [...]`` command (exec form)."""
    (args,) = _instructions("HEALTHCHECK")
    return json.loads(args.split(" CMD ", 1)[1])


def _final_stage() -> str:
    text = re.sub(r"\\\n\s*", " ", DOCKERFILE)
    return text[[m.start() for m in re.finditer(r"^FROM\s", text, re.M)][-1]:]


def workdir_copies() -> list[tuple[Path, str]]:
    """(checkout path, path under the WORKDIR) of every ``COPY`` of the final stage from the
    build context that lands in the image's working directory (``COPY --from`` copies out of
    another stage, not the checkout)."""
    final = _instructions("WORKDIR")[-1]
    workdir = "/"
    copies: list[tuple[Path, str]] = []
    for m in re.finditer(r"^(WORKDIR|COPY)\s+(.*)$", _final_stage(), re.M):
        if m[1] == "WORKDIR":
            workdir = posixpath.join(workdir, m[2].strip())
            continue
        args = m[2].split()
        if args[0].startswith("--"):
            continue
        *sources, dest = args
        into = posixpath.normpath(posixpath.join(workdir, dest))
        if into != final and not into.startswith(final + "/"):
            continue
        rel = posixpath.relpath(into, final)
        for source in sources:
            where = rel if len(sources) == 1 and not dest.endswith("/") else \
                posixpath.join(rel, posixpath.basename(source.rstrip("/")))
            copies.append((ROOT / source, posixpath.normpath(where)))
    return copies


def installed_package(site: Path) -> dict[str, str]:
    """``motionsim`` as the image's ``pip install`` leaves it — a regular package in
    ``site`` (folders linked from the checkout, mapped as pyproject's package-dir says) — and
    the environment whose ``python -S`` imports it from there and the dependencies from this
    venv. Not the checkout's editable install: its import hook finds ``motionsim.app`` even
    when a ``motionsim/`` folder in the working directory shadows the package, which the
    image's plain install does not."""
    package = site / "motionsim"
    package.mkdir(parents=True)
    shutil.copy(ROOT / "motionsim" / "__init__.py", package / "__init__.py")
    for layer in ("sim", "app", "api", "examples"):
        (package / layer).symlink_to(ROOT / layer, target_is_directory=True)
    deps = next(Path(p) for p in sys.path if p.endswith("site-packages"))
    return {"PYTHONPATH": f"{site}{os.pathsep}{deps}"}


def _as_user() -> list[str]:
    if os.geteuid() != 0:
        return []
    setpriv = shutil.which("setpriv")
    assert setpriv, "setpriv (util-linux) drops to the image's uid"
    # CAP_DAC_READ_SEARCH only: the user may read this checkout and its venv wherever CI put
    # them (a root-only folder too), but writes still need the permissions the image grants.
    return [setpriv, f"--reuid={UID}", f"--regid={UID}", "--clear-groups",
            "--inh-caps=+dac_read_search", "--ambient-caps=+dac_read_search", "--"]


@pytest.fixture
def workdir() -> Iterator[Path]:
    """A fresh directory owned by the unprivileged user, like the image's WORKDIR."""
    assert re.search(r"chown -R motionsim:motionsim (\S+)", DOCKERFILE).group(1) == \
        _instructions("WORKDIR")[-1], "the image hands its working directory to its user"
    path = Path(tempfile.mkdtemp(prefix="motionsim-image-"))
    if os.geteuid() == 0:
        os.chown(path, UID, UID)
    try:
        yield path
    finally:
        shutil.rmtree(path, ignore_errors=True)


def _env(workdir: Path, **overrides: str) -> dict[str, str]:
    # Not COVERAGE_* either: under `make cov` a child running as the image's user cannot
    # write the checkout's coverage data, and coverage's own traceback would be its stderr.
    env = {k: v for k, v in os.environ.items() if not k.startswith(("MOTIONSIM_", "COVERAGE_"))}
    env.update(image_env())
    env.update({"HOME": str(workdir), "MPLCONFIGDIR": str(workdir / ".mpl")})
    env.update(overrides)
    return env


def _pmac_command(port: int, line: str) -> bytes:
    """One VR_PMAC_GETRESPONSE (PMAC Ethernet) and its answer."""
    data = line.encode() + b"\0"
    with socket.create_connection(("127.0.0.1", port), timeout=10) as sock:
        sock.sendall(struct.pack(">BBHHH", 0x40, 0xBF, 0, 0, len(data)) + data)
        got = b""
        while not got.endswith(b"\x06"):
            chunk = sock.recv(4096)
            if not chunk:
                break
            got += chunk
    return got


@contextlib.contextmanager
def _image_serving(workdir: Path, *extra: str) -> Iterator[dict[str, int]]:
    """The image's command as its user in ``workdir``, on free ports: scheme -> port."""
    cmd = image_cmd()
    assert cmd[:2] == ["motionsim", "serve"]
    env = _env(workdir, MOTIONSIM_HOST="127.0.0.1", MOTIONSIM_PORT="0",
               MOTIONSIM_PMAC_PORT="auto", MOTIONSIM_TRIO_PORT="auto")
    argv = [*_as_user(), str(BIN / cmd[0]), *cmd[1:], *extra]
    proc = subprocess.Popen(argv, cwd=workdir, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)
    ports: dict[str, int] = {}
    try:
        end = time.monotonic() + 60
        while "http" not in ports and time.monotonic() < end:
            line = proc.stdout.readline()
            if not line:
                break
            if m := re.search(r"listening (\w+)://127\.0\.0\.1:(\d+)", line):
                ports[m.group(1)] = int(m.group(2))
        assert "http" in ports and "pmac" in ports, ports
        yield ports
    finally:
        stop(proc, 15)


def test_the_image_command_serves_as_an_unprivileged_user_and_can_record(workdir):
    with _image_serving(workdir, "--record", "sessions.jsonl") as ports:
        health = [*_as_user(), str(BIN / "python"), "-m", "motionsim.app.healthcheck"]
        ok = subprocess.run(health, env=_env(workdir, MOTIONSIM_PORT=str(ports["http"])),
                            cwd=workdir, capture_output=True, timeout=30)
        assert ok.returncode == 0, ok.stderr
        free = socket.socket()
        free.bind(("127.0.0.1", 0))
        wrong = subprocess.run(health, env=_env(workdir, MOTIONSIM_PORT=str(
            free.getsockname()[1])), cwd=workdir, capture_output=True, timeout=30)
        free.close()
        assert wrong.returncode == 1  # the check follows MOTIONSIM_PORT, not a fixed 8000
        assert _pmac_command(ports["pmac"], "I10").endswith(b"\x06")
    record = workdir / "sessions.jsonl"
    assert record.is_file() and record.stat().st_size > 0
    if os.geteuid() == 0:
        assert record.stat().st_uid == UID


def test_the_health_checks_import_the_installed_package_from_the_working_directory(
        workdir, tmp_path):
    """Docker runs ``HEALTHCHECK`` (and compose's ``healthcheck``) in the image's WORKDIR. A
    ``motionsim/`` source folder there — once the Dockerfile's own ``COPY motionsim
    ./motionsim`` — is first on ``sys.path`` for ``python -m`` and hides the installed
    package (``No module named 'motionsim.app'``): the service never turned healthy and
    compose never started its client (issue 36). Run here the way the image runs them: its
    WORKDIR's files copied from the checkout as its ``COPY``s say, motionsim installed as a
    plain package; then again with a checkout's ``motionsim/`` in that folder, as a user who
    mounts one there would have it."""
    for source, where in workdir_copies():
        target = workdir / where
        target.parent.mkdir(parents=True, exist_ok=True)
        if source.is_dir():
            shutil.copytree(source, target)
        else:
            shutil.copy(source, target)
    installed = installed_package(tmp_path / "site-packages")
    compose = yaml.safe_load((ROOT / "docker-compose.yml").read_text())
    checks = {"Dockerfile HEALTHCHECK": image_healthcheck(),
              "compose healthcheck": compose["services"]["motionsim"]["healthcheck"]["test"][1:]}
    with _image_serving(workdir) as ports:
        for mounted in (False, True):
            if mounted:
                shutil.copytree(ROOT / "motionsim", workdir / "motionsim", dirs_exist_ok=True)
            for name, check in checks.items():
                assert check[0] == "python", check
                argv = [*_as_user(), str(BIN / "python"), "-S", *check[1:]]
                env = _env(workdir, MOTIONSIM_PORT=str(ports["http"]), **installed)
                ran = subprocess.run(argv, env=env, cwd=workdir, capture_output=True,
                                     text=True, timeout=30)
                assert ran.returncode == 0, (name, mounted, ran.stderr)


def test_motionsim_run_writes_its_outputs_in_the_working_directory(workdir):
    scenario = ROOT / "examples" / "scenarios" / "m1_sync.yaml"
    run = subprocess.run([*_as_user(), str(BIN / "motionsim"), "run", str(scenario),
                          "--out", "out"], cwd=workdir, env=_env(workdir),
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stdout + run.stderr
    written = {p.name for p in (workdir / "out").rglob("*") if p.is_file()}
    assert {"events.jsonl", "metrics.json"} <= written


def test_an_output_folder_the_user_cannot_write_is_one_clear_line(workdir):
    locked = workdir / "locked"
    locked.mkdir(mode=0o555)
    if os.geteuid() == 0:
        os.chown(locked, 0, 0)
    scenario = ROOT / "examples" / "scenarios" / "m1_sync.yaml"
    run = subprocess.run([*_as_user(), str(BIN / "motionsim"), "run", str(scenario),
                          "--out", "locked/out"], cwd=workdir, env=_env(workdir),
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 1
    assert "cannot write to locked/out: Permission denied" in run.stderr
    assert "Traceback" not in run.stderr
