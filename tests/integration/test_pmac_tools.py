"""Diamond's PMAC tools, unmodified, against a ``motionsim serve`` subprocess on loopback.

* ``dls-pmac-control`` (the Qt GUI, PyPI ``dls-pmaccontrol``) under ``QT_QPA_PLATFORM=offscreen``:
  connects, fills its axis table (8 rows for a Geo Brick), jogs motor 1 with its "jog +"
  button (``#1J^1000``) and the table shows the new position; its poll thread
  (``i65???&1??%`` then ``#n?PVF m{n}90 p99`` per axis, every 0.1 s) does not spin a core.
* ``dls-pmaclib``'s own API: ``sendCommand``, ``jogInc`` / ``jogTo`` / ``jogStop``,
  ``homeCommand``, motor status read back with ``#n?``.

Facts: spec pmac.md §5.2, §11.9; the tools' sources (dls_pmac_control/__main__.py,
commsThread.py; dls_pmaclib/dls_pmacremote.py).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from tests.integration.test_clients_pmac import free_port, motionsim_serve

HERE = Path(__file__).resolve().parent


def _serve_realtime(pmac_port: int):
    return motionsim_serve("--clock", "realtime", "--pmac-port", str(pmac_port),
                           "--trio-port", "0")


def test_dls_pmac_control_fills_the_axis_table_and_jogs_motor_1() -> None:
    port = free_port()
    with _serve_realtime(port):
        env = {**os.environ, "QT_QPA_PLATFORM": "offscreen"}
        run = subprocess.run([sys.executable, str(HERE / "pmaccontrol_driver.py"), str(port)],
                             capture_output=True, text=True, timeout=90, env=env)
    assert run.returncode == 0, run.stderr[-3000:]
    out = json.loads(next(x for x in run.stdout.splitlines() if x.startswith("{")))
    assert "Geo Brick" in out["title"]
    assert out["rows"] == 8
    assert out["before"] == [["0.0", "0.0", "0.0"]] * 8
    assert out["after"][0] == ["1000.0", "0.0", "0.0"], out["shell"]
    assert out["after"][1:] == [["0.0", "0.0", "0.0"]] * 7
    assert "Received malformed response" not in run.stdout + run.stderr
    assert "Traceback" not in run.stderr, run.stderr[-3000:]
    # the poll thread sleeps 0.1 s between polls; spinning it would cost a whole core
    assert out["cpu_share"] < 0.25, out["cpu_share"]


PMACLIB = r"""
import json, sys, time
from dls_pmaclib.dls_pmacremote import PmacEthernetInterface

p = PmacEthernetInterface(verbose=False, timeout=5.0)
p.setConnectionParams("127.0.0.1", int(sys.argv[1]))
out = {"connect": p.connect(), "log": []}
def send(cmd):
    resp, ok = p.sendCommand(cmd)
    out["log"].append([cmd, resp, ok])
    return resp
def settle(motor):
    for _ in range(200):
        if int(send(f"#{motor}?")[:12], 16) & 1:  # word 2 bit 0: in position
            return
        time.sleep(0.02)
out["axes"] = p.getNumberOfAxes()
out["i124_before"] = send("i124")
out["disable"] = list(p.disableLimits(1, True))
out["i124_disabled"] = send("i124")
out["enable"] = list(p.disableLimits(1, False))
out["i124_enabled"] = send("i124")
send("I122=50 I120=20 I121=0 I119=10 I123=-50")
out["jog_inc"] = p.jogInc(1, "pos", 1000)[1:]
settle(1)
out["p_after_inc"] = send("#1P")
out["jog_to"] = p.jogTo(1, -250)[1:]
settle(1)
out["p_after_to"] = send("#1P")
out["jog_cont"] = p.jogContinous(2, "neg")[1:]
time.sleep(0.3)
out["v_moving"] = send("#2V")
out["jog_stop"] = p.jogStop(2)[1:]
settle(2)
out["v_stopped"] = send("#2V")
out["home"] = p.homeCommand(1)[1:]
out["status_homing"] = send("#1?")
settle(1)
out["status_homed"] = send("#1?")
out["p_homed"] = send("#1P")
out["kill"] = send("#3k")
out["status_killed"] = send("#3?")
out["pvf"] = send("#1?PVF")
p.disconnect()
print(json.dumps(out))
"""


def test_dls_pmaclib_jog_home_and_status_give_the_card_s_answers() -> None:
    port = free_port()
    with _serve_realtime(port):
        run = subprocess.run([sys.executable, "-c", PMACLIB, str(port)],
                             capture_output=True, text=True, timeout=90)
    assert run.returncode == 0, run.stderr[-3000:]
    out = json.loads(run.stdout)
    assert out["connect"] is None
    assert all(ok for _, _, ok in out["log"]), out["log"]
    assert out["axes"] == 8  # a Geo Brick (cid 603382) without MACRO ICs: I20..I23 = $0
    # disableLimits sets Ixx24 bit 17 ($20000) and clears it again, nothing else
    before = int(out["i124_before"].strip("$\r\x06"), 16)
    assert out["disable"] == [f"i124=${before | 0x20000:x}", "\x06", True]
    assert int(out["i124_disabled"].strip("$\r\x06"), 16) == before | 0x20000
    assert out["i124_enabled"] == out["i124_before"]
    assert out["jog_inc"] == ["\x06", True]
    assert out["p_after_inc"] == "1000\r\x06"
    assert out["p_after_to"] == "-250\r\x06"
    assert float(out["v_moving"][:-2]) < -1  # counts per servo cycle, negative jog
    assert out["jog_stop"] == ["\x06", True] and out["v_stopped"] == "0\r\x06"
    homing = int(out["status_homing"][:6], 16)
    assert homing & (1 << 10)  # word 1 bit 10: home search in progress
    homed = int(out["status_homed"][6:12], 16)
    assert homed & (1 << 10) and homed & 1  # home complete, in position
    assert out["p_homed"] == "0\r\x06"
    assert out["kill"] == "\x06"
    assert not int(out["status_killed"][:6], 16) & (1 << 19)  # amplifier disabled
    status, p, v, f = out["pvf"][:-2].split("\r")
    assert (len(status), p, v, f) == (12, "0", "0", "0")
