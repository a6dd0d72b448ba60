"""The container image's command, run as its unprivileged user in a fresh working directory
(no Docker engine here): it serves, its health check follows the configured port, and
``motionsim serve --record`` and ``motionsim run --out`` can write where it runs.

The Dockerfile is read for what the image does (``ENV MOTIONSIM_*``, ``CMD``, the ``chown`` of
its ``WORKDIR``); the test mirrors it with a temporary directory owned by an unprivileged uid
and ``setpriv`` (CI runs as root; a developer who is not root already is unprivileged). The
user keeps only the right to read files anywhere (the checkout may sit in a root-only folder);
writing still needs what the image gives it."""

from __future__ import annotations

import json
import os
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


def test_the_image_command_serves_as_an_unprivileged_user_and_can_record(workdir):
    cmd = image_cmd()
    assert cmd[:2] == ["motionsim", "serve"]
    env = _env(workdir, MOTIONSIM_HOST="127.0.0.1", MOTIONSIM_PORT="0",
               MOTIONSIM_PMAC_PORT="auto", MOTIONSIM_TRIO_PORT="auto")
    argv = [*_as_user(), str(BIN / cmd[0]), *cmd[1:], "--record", "sessions.jsonl"]
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
    finally:
        stop(proc, 15)
    record = workdir / "sessions.jsonl"
    assert record.is_file() and record.stat().st_size > 0
    if os.geteuid() == 0:
        assert record.stat().st_uid == UID


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
