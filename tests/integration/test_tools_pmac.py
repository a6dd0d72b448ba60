"""Diamond's Turbo PMAC tools, unmodified, against a ``motionsim serve`` subprocess on loopback.

* dls-pmacanalyse (``python -m dls_pmacanalyse.dls_pmacanalyse --pmac=… --tcpip=host:port
  --backup=DIR``) reads the whole card (I/P/Q/M variables, M definitions, axis definitions,
  PLC, PROG and kinematic listings) and writes a backup that holds what was loaded;
* dls-backup-bl backs a controller up (through dls-pmacanalyse, then ``save``), saves motor
  positions (Mxx62, Mxx45, M5001..5032) and restores them (CTRL-K, then Mxx62 writes). It
  dials the PMAC Ethernet port only when the configured port is 1025, so motionsim serves on
  port 1025 of a 127.x.y.z address of its own;
* dls-pmaclib's API: the axis count (8: a Geo Brick with no MACRO IC), ``sendCommand``.

Each tool runs in a process of its own with a timeout; the controller is checked over REST.
"""

from __future__ import annotations

import json
import random
import re
import socket
import subprocess
import sys
from pathlib import Path

import httpx
import pytest

from tests.integration.test_clients_pmac import free_port, motionsim_serve

TOOL_TIMEOUT_S = 300

PLC1 = ["OPEN PLC 1 CLEAR", "IF (M4900 = 0)", "M4900 = 1", "ENDIF", "CLOSE"]
SETUP = [*PLC1, "M1->Y:$78802,8", "M162->D:$00008B", "M145->Y:$0000C0,10,1", "P10=5",
         "&1 #1->1000X", "#1HMZ", "I130=1234"]  # fmt: skip


def _terminal(http: str, lines: list[str]) -> None:
    for line in lines:
        body = httpx.post(f"{http}/controllers/pmac/terminal", json={"command": line},
                          timeout=10).json()
        assert body["error"] is None, (line, body)


def _move_motor_1(http: str, x: float) -> None:
    """Move CS 1's X (motor 1, 1000 counts per unit) to ``x`` through its rotary program."""
    if httpx.get(f"{http}/controllers/pmac/coord/1", timeout=10).json()["rotary"] is None:
        _terminal(http, ["&1 DEFINE ROT 100", "&1 B0 R"])
    _terminal(http, ["OPEN ROT", f"&1 X{x}", "CLOSE"])
    httpx.post(f"{http}/controllers/pmac/clock/advance", json={"seconds": 10}, timeout=30)


def _pmacanalyse(tmp_path: Path, port: int, *args: str) -> str:
    run = subprocess.run(
        [sys.executable, "-m", "dls_pmacanalyse.dls_pmacanalyse", "--pmac=sim",
         f"--tcpip=127.0.0.1:{port}", *args],
        capture_output=True, text=True, timeout=TOOL_TIMEOUT_S, cwd=tmp_path)
    log = run.stdout + run.stderr
    assert run.returncode == 0, log
    return log


def test_pmacanalyse_reads_the_whole_card_and_backs_up_what_was_loaded(tmp_path: Path) -> None:
    port = free_port()
    backup_dir = tmp_path / "backup"
    with motionsim_serve("--pmac-port", str(port), "--trio-port", "0") as svc:
        _terminal(svc.http, SETUP)
        log = _pmacanalyse(tmp_path, port, f"--backup={backup_dir}",
                           f"--resultsdir={tmp_path / 'results'}")
        # its own backup as the reference: the card reads back exactly as it was saved
        same = _pmacanalyse(tmp_path, port, f"--reference={backup_dir / 'sim.pmc'}",
                            f"--resultsdir={tmp_path / 'compare'}")
        _terminal(svc.http, ["P10=6"])
        changed = _pmacanalyse(tmp_path, port, f"--reference={backup_dir / 'sim.pmc'}",
                               f"--resultsdir={tmp_path / 'compare2'}")
    assert "Hardware matches reference" in same, same
    assert "Hardware to reference mismatch detected" in changed, changed
    assert "Geobrick= True" in log and "Num axes= 8" in log
    assert "Error" not in log and "Traceback" not in log, log
    backup = (tmp_path / "backup" / "sim.pmc").read_text()
    plc = backup[backup.index("open plc 1 clear"):]
    assert plc.splitlines()[:5] == ["open plc 1 clear", "IF(M4900=0)", "M4900=1", "ENDIF",
                                    "RETURN"]
    assert "\nm1->Y:$78802,8\n" in backup and "\nm162->D:$8b\n" in backup
    assert "\np10=5\n" in backup and "\n&1#1->1000X\n" in backup
    assert "\ni130=1234\n" in backup and "\ni124=$40001\n" in backup
    assert "\ni68=15\n" in backup  # 16 coordinate systems read
    assert len(re.findall(r"^&16#32->0$", backup, re.M)) == 1
    assert (tmp_path / "results" / "index.htm").exists()


def _loopback_address() -> str:
    """A 127.x.y.z address nobody else on this machine is likely to serve port 1025 on."""
    for _ in range(20):
        host = f"127.{random.randint(1, 254)}.{random.randint(1, 254)}.{random.randint(2, 254)}"
        with socket.socket() as s:
            try:
                s.bind((host, 1025))
            except OSError:
                continue
            return host
    pytest.fail("no free 127.x.y.z:1025")


def _backup_bl(tmp_path: Path, host: str, *args: str, stdin: str = "") -> str:
    cfg = tmp_path / "backup.json"
    cfg.write_text(json.dumps({
        "motion_controllers": [{"controller": "SIM-MO-BRICK-01", "server": host,
                                "port": 1025}],
        "terminal_servers": [], "zebras": []}))
    run = subprocess.run(
        [sys.executable, "-m", "dls_backup_bl", "--dir", str(tmp_path / "bk"), "-j", str(cfg),
         "--domain", "SIM", "-r", "1", "-t", "1", "-l", "info", *args],
        capture_output=True, text=True, timeout=TOOL_TIMEOUT_S, cwd=tmp_path, input=stdin,
        env={**__import__("os").environ, "HOME": str(tmp_path)})
    log = run.stdout + run.stderr
    assert run.returncode == 0, log
    return log


def test_backup_bl_backs_up_saves_and_restores_motor_positions(tmp_path: Path) -> None:
    host = _loopback_address()
    with motionsim_serve("--host", host, "--pmac-port", "1025", "--trio-port", "0") as svc:
        http = svc.http.replace("127.0.0.1", host)
        _terminal(http, SETUP)
        _move_motor_1(http, 2)
        log = _backup_bl(tmp_path, host)
        assert "SUCCESS: pmac SIM-MO-BRICK-01" in log and "backed up" in log, log
        folder = tmp_path / "bk" / "MotionControllers"
        backup = (folder / "SIM-MO-BRICK-01.pmc").read_text()
        assert "open plc 1 clear" in backup and "\np10=5\n" in backup

        log = _backup_bl(tmp_path, host, "-p", "save")
        assert "SUCCESS: positions retrieved" in log, log
        positions = (folder / "SIM-MO-BRICK-01_positions.pmc").read_text()
        assert f"M162 = {2000 * 96 * 32}\n" in positions  # Mxx62 in 1/(Ixx08*32) counts
        assert "M145 = 1\n" in positions  # home complete (#1HMZ; motor status word 2, bit 10)

        _move_motor_1(http, 5)
        assert httpx.post(f"{http}/controllers/pmac/terminal",
                          json={"command": "#1P"}).json()["reply"] == "5000"
        log = _backup_bl(tmp_path, host, "-p", "restore", stdin="y\n")
        assert "SUCCESS: positions restored" in log and "failed for" not in log, log
        reply = httpx.post(f"{http}/controllers/pmac/terminal", json={"command": "#1P"},
                           timeout=10).json()["reply"]
    assert float(reply) == pytest.approx(2000, abs=0.1)


PMACLIB = r"""
import json, sys
from dls_pmaclib.dls_pmacremote import PmacEthernetInterface
p = PmacEthernetInterface(verbose=False, timeout=5.0)
p.setConnectionParams("127.0.0.1", int(sys.argv[1]))
out = {"connect": p.connect(), "model": p.getPmacModel(), "axes": p.getNumberOfAxes()}
out["i20"] = p.sendCommand("i20..23")
out["m"] = [p.sendCommand(c) for c in ("M1->Y:$78802,8", "M1=1", "M1", "M1->")]
out["bad"] = p.sendCommand("i10 nonsense")
out["after"] = p.sendCommand("i16")
long = p.sendCommand("i0..1023")
out["long_lines"] = len(long[0].split("\r")) - 1
out["long_ok"] = long[1] and long[0].endswith("\r\x06")
out["after_long"] = p.sendCommand("i17")
out["cr1400"] = p.sendCommand("p0..699")  # 700 x "0\r": a CR at byte 1400
out["after_cr"] = p.sendCommand("i16")
pmc = open(sys.argv[2]).read().splitlines()  # a .pmc file of definitions, line by line
out["series"] = [ok for ok, _n, _cmd, _resp in p.sendSeries(list(enumerate(pmc, 1)))]
out["defs"] = p.sendCommand("M1..3->")
out["values"] = p.sendCommand("M1..3")
p.disconnect()
print(json.dumps(out))
"""

PMC = """; output bits of a Geo Brick and a position register
M1->Y:$078802,8,1
M2->Y:$078802,9,1 ; second output
M3->Y:$078802,8,8
M1=1
M2=1
"""


def test_pmaclib_counts_8_axes_and_its_commands_answer_in_order(tmp_path: Path) -> None:
    port = free_port()
    pmc = tmp_path / "defs.pmc"
    pmc.write_text(PMC)
    with motionsim_serve("--pmac-port", str(port), "--trio-port", "0"):
        run = subprocess.run([sys.executable, "-c", PMACLIB, str(port), str(pmc)],
                             capture_output=True, text=True, timeout=TOOL_TIMEOUT_S)
    assert run.returncode == 0, run.stderr
    out = json.loads(run.stdout)
    assert out["connect"] is None and out["axes"] == 8
    assert out["model"] == "Geo Brick (3U Turbo PMAC2)"
    assert out["i20"] == ["$0\r$0\r$0\r$0\r\x06", True]
    assert [r for r, _ in out["m"]] == ["\x06", "\x06", "1\r\x06", "Y:$78802,8\r\x06"]
    assert out["bad"] == ["3713707\r\x07ERR003\r", True]
    assert out["after"] == ["5\r\x06", True]  # the session is not a reply behind
    assert out["long_lines"] == 1024 and out["long_ok"]  # > 1400 bytes: GETBUFFER pieces
    assert out["after_long"] == ["10\r\x06", True]
    assert out["cr1400"] == ["0\r" * 700 + "\x06", True]
    assert out["after_cr"] == ["5\r\x06", True]
    assert out["series"] == [True] * len(PMC.splitlines())
    assert out["defs"] == ["Y:$78802,8\rY:$78802,9\rY:$78802,8,8\r\x06", True]
    assert out["values"] == ["1\r1\r3\r\x06", True]
