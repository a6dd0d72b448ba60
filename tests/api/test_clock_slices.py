"""Issue: no request freezes the service. Simulation runs in bounded slices on the one loop.

A long virtual ``advance`` / ``run-until`` on a busy PMAC (a PLC 1 scanning every background
cycle) lets ``/health`` and other controllers be served meanwhile, is cancelled when its client
disconnects, and produces exactly the log of the same advance done in one go.
"""

from __future__ import annotations

import asyncio
import json
import time

import httpx
import pytest
from motionsim.api.main import create_app
from motionsim.app import clock as clock_module
from motionsim.app.embedded import EmbeddedService
from motionsim.app.settings import Settings

from tests.conftest import rest_client

pytestmark = pytest.mark.anyio

PLC = "P1=P1+1\nP2=P1*2\nIF (P2>100)\nP3=P3+1\nENDIF"


def _settings() -> Settings:
    return Settings(controllers=[{"id": "p", "kind": "pmac", "clock": {"mode": "virtual"}},
                                 {"id": "q", "kind": "pmac", "clock": {"mode": "virtual"}}],
                    pmac_port=0, trio_port=0)


async def _busy(api: httpx.AsyncClient, cid: str = "p") -> None:
    """PLC 1 runs every background cycle (I5 = 3); a rotary program streams 5 ms moves."""
    await api.put(f"/controllers/{cid}/variables/I5", json={"value": 3})
    r = await api.put(f"/controllers/{cid}/plcs/1", json={"text": PLC})
    assert r.status_code == 200, r.text
    assert (await api.post(f"/controllers/{cid}/plcs/1/enable")).status_code == 200
    await api.put(f"/controllers/{cid}/coord/1/rotary", json={"size_words": 600})
    await api.post(f"/controllers/{cid}/coord/1/rotary/lines",
                   json={"lines": [f"TM5 TA1 TS0 X{i}" for i in range(50)]})
    await api.post(f"/controllers/{cid}/coord/1/run")


async def _log(api: httpx.AsyncClient, cid: str = "p") -> str:
    events, since = [], 0
    while True:
        page = (await api.get(f"/controllers/{cid}/events",
                              params={"since": since, "limit": 10000})).json()
        events += page["events"]
        if page["next"] == since:
            return "\n".join(json.dumps(e, sort_keys=True) for e in events)
        since = page["next"]


async def test_health_and_another_controller_are_served_during_a_long_advance():
    async with rest_client(create_app(_settings())) as api:
        await _busy(api)
        advance = asyncio.ensure_future(
            api.post("/controllers/p/clock/advance", json={"seconds": 5.0}))
        await asyncio.sleep(0.05)
        health = await api.get("/health")
        other = await api.post("/controllers/q/clock/advance", json={"seconds": 0.1})
        t_mid = (await api.get("/controllers/p/clock")).json()["t"]
        assert not advance.done()          # served while p was still computing
        assert health.status_code == 200 and other.json()["t"] == pytest.approx(0.1)
        assert 0 < t_mid < 5.0             # p was part-way (a slice boundary)
        r = await advance
        assert r.json()["t"] == pytest.approx(5.0)


#: Reads the sliced advance is interleaved with. A slice is wall time (``SLICE_S``), so how
#: many slices 2 simulated seconds take grows as the machine slows: the reads are bounded, not
#: one per slice (20 000 of them timed out on a loaded machine).
READS_BETWEEN_SLICES = 300


async def test_a_sliced_advance_gives_the_same_log_as_one_unsliced(monkeypatch):
    """Slices change nothing in the log: the same busy minute in ~0.1 ms slices (thousands of
    loop turns, the first ones with other requests in between) and in one slice are
    byte-identical."""
    logs = []
    for slice_s in (1e-4, 3600.0):
        monkeypatch.setattr(clock_module, "SLICE_S", slice_s)
        async with rest_client(create_app(_settings())) as api:
            handle = api.app.state.registry.get("p")
            handle.clock.slice_s = slice_s
            await _busy(api)
            go = asyncio.ensure_future(
                api.post("/controllers/p/clock/advance", json={"seconds": 2.0}))
            reads = 0
            while not go.done() and reads < READS_BETWEEN_SLICES:
                await api.get("/controllers/p")   # reads between slices change nothing
                await asyncio.sleep(0)            # (in process, a request never waits on I/O)
                reads += 1
            assert (await go).status_code == 200
            p1 = (await api.get("/controllers/p/variables/P1")).json()["value"]
            logs.append((await _log(api), p1))
    assert logs[0] == logs[1]
    assert logs[0][0].count("\n") > 200 and logs[0][1] > 1000  # moves streamed, PLC 1 scanned


async def test_run_until_for_an_event_that_never_comes_does_not_block_others():
    async with rest_client(create_app(_settings())) as api:
        await _busy(api)
        wait = asyncio.ensure_future(api.post("/controllers/p/clock/run-until", json={
            "event": {"type": "watchdog"}, "timeout_s": 3.0}))
        await asyncio.sleep(0.05)
        assert (await api.get("/health")).status_code == 200
        assert not wait.done()
        body = (await wait).json()
        assert (body["matched"], body["outcome"]) == (None, "timeout")
        assert body["clock"]["t"] == pytest.approx(3.0)


def test_an_advance_is_cancelled_when_its_client_disconnects():
    """Over a real socket: the client gives up (read timeout, connection closed); the server
    stops the advance at a slice boundary instead of computing on for nobody."""
    with EmbeddedService(_settings().model_copy(update={"port": 0})) as svc:
        with httpx.Client(base_url=svc.url, trust_env=False) as c:
            c.put("/controllers/p/variables/I5", json={"value": 3})
            c.put("/controllers/p/plcs/1", json={"text": PLC})
            c.post("/controllers/p/plcs/1/enable")
            with pytest.raises(httpx.ReadTimeout):
                c.post("/controllers/p/clock/advance", json={"seconds": 3600.0},
                       timeout=httpx.Timeout(5.0, read=0.5))
        with httpx.Client(base_url=svc.url, trust_env=False, timeout=30) as c:
            # the server notices at its next slice boundary, which a loaded machine delays:
            # wait (bounded) until the clock stands still, then check it stays there
            reads = [c.get("/controllers/p/clock").json()["t"]]
            for _ in range(60):
                time.sleep(0.5)
                reads.append(c.get("/controllers/p/clock").json()["t"])
                if reads[-1] == reads[-2]:
                    break
            time.sleep(0.5)
            final = c.get("/controllers/p/clock").json()["t"]
        assert reads[-1] == reads[-2], reads   # it stopped ...
        assert 0 < final == reads[-1] < 3600.0  # ... part-way, and nothing runs on after
