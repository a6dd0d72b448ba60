"""``motionsim run --realtime``: the scenario played on a running server over REST (one
short run on 127.0.0.1, simulated time 2x the wall clock).

The host is a real HTTP client racing the wall clock: at 2x it has 0.5 s of wall time for the
105 lines and the polls (at 10x, 0.1 s, a loaded CI machine could make it miss lines), so
the exact counts below hold however busy the machine is.
"""

from __future__ import annotations

from motionsim.app.client import MotionSimClient
from motionsim.app.embedded import EmbeddedService
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
        rep = play(scn, svc.url, factor=2.0, echo=lambda *_: None)
        with MotionSimClient(svc.url) as c:
            scans, stored = c.get_variable("rt_pmac", "P1"), c.get_variable("rt_pmac", "P2")
            plc2 = c.request("GET", "/controllers/rt_pmac/plcs/2")
    m = rep["controllers"]["rt_pmac"]["cs"][1]
    assert m["lines_loaded"] == 105  # header + 100 moves, all sent over HTTP
    assert m["lines_executed"] > 50
    assert m["host_writes"] == 0  # no host_* events: the host was remote
    # PLC programs stored over REST; PLC 0 enabled (scans every RTI), PLC 2 only stored
    assert scans > 100 and stored == 0
    assert plc2["program"] == ["P2=P2+1"] and plc2["enabled"] is False
