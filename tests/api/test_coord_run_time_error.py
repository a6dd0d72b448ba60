"""REST view of a PMAC run-time error (TUM p339): calculation fell behind 1 ms moves."""

from __future__ import annotations

import pytest

pytestmark = pytest.mark.anyio

BASE = "/controllers/p"


async def test_coord_shows_the_run_time_error_and_the_next_run_clears_it(pmac_api):
    api = pmac_api
    await api.put(f"{BASE}/coord/1/rotary", json={"size_words": 600})
    lines = ["LINEAR ABS TA1 TS0 TM1"] + [f"X{i}" for i in range(1, 30)]
    await api.post(f"{BASE}/coord/1/rotary/lines", json={"lines": lines})
    await api.post(f"{BASE}/coord/1/run")
    await api.post(f"{BASE}/clock/advance", json={"seconds": 0.1})
    program = (await api.get(f"{BASE}/coord/1")).json()["program"]
    assert (program["state"], program["error"]) == ("aborted", "run_time_error")
    ev = (await api.get(f"{BASE}/events", params={"type": "program"})).json()["events"]
    assert ev[-1]["state"] == "aborted" and ev[-1]["error"] == "run_time_error"
    r = await api.post(f"{BASE}/terminal", json={"command": "I8=0"})
    assert r.json()["error"] is None
    program = (await api.post(f"{BASE}/coord/1/run")).json()["program"]
    assert program["state"] == "running" and program["error"] is None
