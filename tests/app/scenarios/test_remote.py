"""``motionsim run --realtime``: the scenario played on a running server over REST (one
short run on 127.0.0.1, simulated time 2x the wall clock).

The host is a real HTTP client racing the wall clock: at 2x it has 0.5 s of wall time for the
105 lines and the polls (at 10x, 0.1 s, a loaded CI machine could make it miss lines), so
the exact counts below hold however busy the machine is.
"""

from __future__ import annotations

import json
import socket
import subprocess
import sys

import pytest
from motionsim.app.client import MotionSimClient
from motionsim.app.embedded import EmbeddedService
from motionsim.app.scenarios.errors import ScenarioError
from motionsim.app.scenarios.model import loads_scenario
from motionsim.app.scenarios.remote import play
from motionsim.app.settings import Settings

SCENARIO = """\
name: remote
duration_s: 1.0
controllers:
  rt_pmac:
    kind: pmac
    rotary:
      - {cs: 1, size_words: 200}
    plcs:
      - {plc: 0, text: "P1=P1+1"}
      - {plc: 2, text: "P2=P2+1", enabled: false}
hosts:
  - type: pr_polling
    poll_period_ms: 20
    lines_per_write: 20
    high_water: 40
    low_water: 20
    program:
      generate: {moves: 100, move_ms: 2, axes: 2}
"""


def test_realtime_play_streams_the_program_and_reports_from_server_events():
    scn = loads_scenario(SCENARIO)
    settings = Settings(port=0, pmac_port=0, trio_port=0)
    with EmbeddedService(settings) as svc:
        rep, run = play(scn, svc.url, factor=2.0, echo=lambda *_: None)
        with MotionSimClient(svc.url) as c:
            # the scenario's controller is created as "<scenario name>-<id>" on the server
            scans = c.get_variable("remote-rt_pmac", "P1")
            stored = c.get_variable("remote-rt_pmac", "P2")
            plc2 = c.request("GET", "/controllers/remote-rt_pmac/plcs/2")
    assert rep["controllers"]["rt_pmac"]["server_id"] == "remote-rt_pmac"
    assert [e.seq for e in run.events("rt_pmac")][:3] == [1, 2, 3]
    m = rep["controllers"]["rt_pmac"]["cs"][1]
    assert m["lines_loaded"] == 105  # header + 100 moves, all sent over HTTP
    assert m["lines_executed"] > 50
    assert m["host_writes"] == 0  # no host_* events: the host was remote
    # PLC programs stored over REST; PLC 0 enabled (scans every RTI), PLC 2 only stored
    assert scans > 100 and stored == 0
    assert plc2["program"] == ["P2=P2+1"] and plc2["enabled"] is False


SHORT = SCENARIO.replace("duration_s: 1.0", "duration_s: 0.2").replace(
    "generate: {moves: 100, move_ms: 2, axes: 2}", "generate: {moves: 10, move_ms: 2, axes: 2}")


def test_an_existing_server_controller_is_never_replaced_without_replace():
    """Issue 36 item 3: a realtime run used to delete and re-create every server controller
    whose id the scenario uses (on a `make run` server, the PMAC port's own ``pmac``)."""
    scn = loads_scenario(SHORT.replace("rt_pmac:", "pmac:"))
    settings = Settings(port=0, pmac_port=0, trio_port=0)
    with EmbeddedService(settings) as svc, MotionSimClient(svc.url) as c:
        c.set_variable("pmac", "P77", 12.0)
        # the default prefix keeps it apart: "remote-pmac" is created, "pmac" untouched
        play(scn, svc.url, factor=2.0, echo=lambda *_: None)
        assert c.get_variable("pmac", "P77") == 12.0
        # no prefix: the id is taken, the run is refused before anything is made
        before = [x["id"] for x in c.controllers()]
        with pytest.raises(ScenarioError, match=r"already has controller\(s\) pmac: --replace"):
            play(scn, svc.url, factor=2.0, echo=lambda *_: None, prefix="")
        assert [x["id"] for x in c.controllers()] == before
        assert c.get_variable("pmac", "P77") == 12.0
        # a second run under the same prefix is refused too; --replace does it
        with pytest.raises(ScenarioError, match="remote-pmac"):
            play(scn, svc.url, factor=2.0, echo=lambda *_: None)
        c.set_variable("remote-pmac", "P77", 5.0)
        play(scn, svc.url, factor=2.0, echo=lambda *_: None, replace=True)
        assert c.get_variable("remote-pmac", "P77") == 0.0  # re-created
        assert c.get_variable("pmac", "P77") == 12.0


def test_a_bad_prefix_is_refused_naming_it():
    scn = loads_scenario(SHORT)
    with pytest.raises(ScenarioError, match=r"--id-prefix 'a b': 'a brt_pmac' is not a"):
        play(scn, "http://127.0.0.1:9", prefix="a b")


def _closed_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _motionsim(*args: str, cwd) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "motionsim", *args], cwd=cwd,
                          capture_output=True, text=True, timeout=120)


def test_no_server_there_is_one_line_not_a_traceback(tmp_path):
    (tmp_path / "s.yaml").write_text(SHORT)
    url = f"http://127.0.0.1:{_closed_port()}"
    r = _motionsim("run", "s.yaml", "--realtime", "--server", url, cwd=tmp_path)
    assert r.returncode == 1
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"motionsim: cannot reach the server at {url}")
    assert "Traceback" not in r.stderr


def test_realtime_writes_the_files_a_virtual_run_writes(tmp_path):
    """``--out`` / ``--plots`` are honoured with --realtime: events.jsonl, events.csv,
    metrics.json and the PNGs, from the server's event log, keyed by the scenario's ids."""
    (tmp_path / "s.yaml").write_text(SHORT)
    with EmbeddedService(Settings(port=0, pmac_port=0, trio_port=0)) as svc:
        r = _motionsim("run", "s.yaml", "--realtime", "--server", svc.url, "--factor", "2",
                       "--out", "rt", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    out = tmp_path / "rt"
    names = sorted(p.name for p in out.iterdir())
    assert {"events.jsonl", "events.csv", "metrics.json"} <= set(names)
    assert any(n.endswith(".png") for n in names)
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["stopped_by"] == "realtime"
    assert metrics["controllers"]["rt_pmac"]["server_id"] == "remote-rt_pmac"
    rows = [json.loads(x) for x in (out / "events.jsonl").read_text().splitlines()]
    assert rows and {x["controller"] for x in rows} == {"rt_pmac"}
    assert sum(1 for x in rows if x["type"] == "line_loaded") == 15  # header + 10 moves
    assert f"wrote {len(names)} files to rt" in r.stdout
