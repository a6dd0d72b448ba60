"""``motionsim`` as a user runs it: real subprocesses on 127.0.0.1.

The integration test is the docker-compose topology without Docker: one process serves
(``motionsim serve --port 0``), another process is the client, talking over 127.0.0.1.
"""

from __future__ import annotations

import json
import os
import re
import socket
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from tests.processes import stop

ROOT = Path(__file__).resolve().parents[2]
MOTIONSIM = Path(sys.executable).parent / "motionsim"
ENV = {**os.environ, "PYTHONPATH": str(ROOT), "PYTHONUNBUFFERED": "1"}


def _run(*args, timeout=30):
    return subprocess.run([str(MOTIONSIM), *args], capture_output=True, text=True,
                          timeout=timeout, env=ENV, cwd=ROOT)


def test_version():
    r = _run("--version")
    assert r.returncode == 0
    assert re.fullmatch(r"motionsim \d+\.\d+\.\d+\n", r.stdout)


def test_serve_help_explains_every_option():
    r = _run("serve", "--help")
    assert r.returncode == 0
    for option in ["--host", "--port", "--clock", "--factor", "--pmac-port", "--trio-port",
                   "--config"]:
        assert option in r.stdout


def test_bad_option_values_exit_non_zero_with_a_message():
    r = _run("serve", "--clock", "sometimes")
    assert r.returncode != 0 and "--clock" in r.stderr
    r = _run("serve", "--pmac-port", "x")
    assert r.returncode != 0 and "--pmac-port" in r.stderr


def _config(tmp_path, **extra):
    cfg = {"plugins": ["tests.dummy_kind"], "clock": {"mode": "virtual"},
           "controllers": [{"id": "d", "kind": "dummy"}], "pmac_port": 0, "trio_port": 0}
    cfg.update(extra)
    path = tmp_path / "motionsim.json"
    path.write_text(json.dumps(cfg))
    return path


class _Served:
    def __init__(self, proc, lines):
        self.proc, self.lines = proc, lines

    @property
    def url(self):
        for line in self.lines:
            m = re.match(r"motionsim listening (http://127\.0\.0\.1:\d+)$", line)
            if m:
                return m.group(1)
        return None


def _serve(*args, deadline_s=30):
    proc = subprocess.Popen([str(MOTIONSIM), "serve", *args], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=ENV, cwd=ROOT)
    served = _Served(proc, [])
    end = time.monotonic() + deadline_s
    while time.monotonic() < end and served.url is None:
        line = proc.stdout.readline()
        if not line:
            break
        served.lines.append(line.rstrip("\n"))
    return served


def _stop(served):
    stop(served.proc)


CLIENT = textwrap.dedent("""
    import json, sys, time
    from motionsim.app.client import MotionSimClient
    ms = MotionSimClient(sys.argv[1])
    for _ in range(200):
        if ms.health():
            break
        time.sleep(0.05)
    out = {}
    out["controllers"] = [c["id"] for c in ms.controllers()]
    out["echo"] = ms.terminal("d", "ECHO over tcp").reply
    out["clock"] = ms.advance("d", 0.05).t
    with ms.subscribe("d", since=0, types=["tick"], timeout=5) as events:
        out["ticks"] = [next(events)["n"] for _ in range(5)]
    out["matched"] = ms.run_until("d", "tick", 1.0, n=8).matched["t"]
    print(json.dumps(out))
""")


def test_serve_on_a_free_port_and_drive_it_from_another_process(tmp_path):
    served = _serve("--port", "0", "--config", str(_config(tmp_path)))
    try:
        assert served.url, f"no listening line; stdout={served.lines}"
        client = subprocess.run([sys.executable, "-c", CLIENT, served.url], capture_output=True,
                                text=True, timeout=60, env=ENV, cwd=ROOT)
        assert client.returncode == 0, client.stderr
        out = json.loads(client.stdout)
        assert out["controllers"] == ["d"]
        assert out["echo"] == "over tcp"
        assert out["clock"] == pytest.approx(0.0505)
        assert out["ticks"] == [1, 2, 3, 4, 5]
        assert out["matched"] == pytest.approx(0.08)
    finally:
        _stop(served)
    assert served.proc.returncode in (0, -15)


def test_an_asked_for_port_that_cannot_be_bound_is_an_error_exit(tmp_path):
    busy = socket.socket()
    busy.bind(("127.0.0.1", 0))
    busy.listen(1)
    port = busy.getsockname()[1]
    try:
        r = _run("serve", "--port", str(port), "--config", str(_config(tmp_path)))
        assert r.returncode == 1
        assert f"cannot listen on http://127.0.0.1:{port}" in r.stderr
        r = _run("serve", "--port", "0", "--pmac-port", str(port),
                 "--config", str(_config(tmp_path, controllers=[{"id": "pmac",
                                                                 "kind": "dummy"}])))
        assert r.returncode == 1
        assert str(port) in r.stderr
    finally:
        busy.close()


def test_invalid_config_file_is_an_error_exit(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("clock: {mode: sometimes}\n")
    r = _run("serve", "--config", str(bad))
    assert r.returncode == 2
    assert "clock.mode" in r.stderr
