"""A real host (dls-pmaclib over the PMAC Ethernet protocol) streams SPLINE1 points into a
rotary buffer of ``motionsim serve``; the REST clock runs the program and the event log shows
the spline's timing (TUM p290: N points take (N + 2)·T with the added start and end segments)
and ``??`` word 2 the SPLINE mode bits (TSRM p286: bits 4, 1, 0 = 1, 0, 1)."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import httpx

from tests.integration.test_clients_pmac import free_port, motionsim_serve

CLIENT = r"""
import json, sys
from dls_pmaclib.dls_pmacremote import PmacEthernetInterface

p = PmacEthernetInterface(verbose=False, timeout=5.0)
p.setConnectionParams("127.0.0.1", int(sys.argv[1]))
p.connect()
print(json.dumps([p.sendCommand(cmd) for cmd in json.loads(sys.argv[2])]))
p.disconnect()
"""
LINES = ["&1 DEFINE ROT 600", "&1 B0", "OPEN ROT", "ABS SPLINE1 TM100 X10", "X20", "X40", "X40",
         "CLOSE", "&1 R"]


def _client(port: int, lines: list[str]) -> list[list]:
    client = subprocess.run([sys.executable, "-c", CLIENT, str(port), json.dumps(lines)],
                            capture_output=True, text=True, timeout=60)
    assert client.returncode == 0, client.stderr
    return json.loads(client.stdout)


def test_tum_p290_dls_pmaclib_streams_spline1_points_and_the_series_takes_n_plus_2_t() -> None:
    pmac_port = free_port()
    with motionsim_serve("--pmac-port", str(pmac_port), "--trio-port", "0") as svc:
        replies = _client(pmac_port, LINES)
        http = svc.http + "/controllers/pmac"
        for event in ({"type": "move_start", "n": 2}, {"type": "program", "state": "waiting"}):
            run = httpx.post(http + "/clock/run-until", timeout=30, json={
                "event": event, "timeout_s": 10})
            assert run.json()["matched"] is not None
            if event["type"] == "move_start":
                replies += _client(pmac_port, ["&1 ??"])
        events = httpx.get(http + "/events", timeout=5, params={
            "type": ["move_start", "move_end"]}).json()["events"]
    assert all(ok for _, ok in replies), replies
    assert [r for r, _ in replies[:9]] == ["\x06"] * 9
    w2 = int(replies[9][0][6:12], 16)
    assert (w2 >> 4 & 1, w2 >> 1 & 1, w2 & 1) == (1, 0, 1)
    start = {e["n"]: e["t"] for e in events if e["type"] == "move_start"}
    end = {e["n"]: e["t"] for e in events if e["type"] == "move_end"}
    assert sorted(start) == sorted(end) == [1, 2, 3, 4]
    period = 1 / 2258.0  # the factory servo rate (I10)
    assert math.isclose(end[4] - start[1], 0.6, abs_tol=period)
    assert math.isclose(end[1] - start[1], 0.2, abs_tol=period)
