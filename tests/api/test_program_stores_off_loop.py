"""Large program stores do not hold the event loop (issue 23, item 1).

A Trio program of hundreds of kilobytes or a PLC of thousands of lines takes seconds to
compile; it is compiled in the service's worker thread while ``/health`` and every other
client are served, then stored all or nothing as before (a parse error: 422, nothing stored).
"""

from __future__ import annotations

import asyncio
import gc

import pytest

pytestmark = pytest.mark.anyio


async def _with_ticker(call) -> tuple[object, list[float]]:
    """Await ``call`` while a ticker records the event loop's gaps between 5-ms sleeps."""
    gaps: list[float] = []

    async def ticker() -> None:
        loop = asyncio.get_running_loop()
        last = loop.time()
        while True:
            await asyncio.sleep(0.005)
            now = loop.time()
            gaps.append(now - last)
            last = now

    gc.collect()
    gc.freeze()  # the test process's own heap (earlier tests) is not what is measured
    ticking = asyncio.ensure_future(ticker())
    try:
        result = await call
    finally:
        ticking.cancel()
        gc.unfreeze()
    return result, gaps


TRIO_PROGRAM = "\n".join(f"VR({i % 500})=VR({i % 500})+{i}*2" for i in range(6000))
PLC_TEXT = "\n".join(f"P{i % 900}=P{i % 900}+{i}*2+SIN(P{(i + 1) % 900})" for i in range(4000))


async def test_a_large_trio_program_compiles_while_the_loop_serves_others(trio_api):
    r, gaps = await _with_ticker(trio_api.put(
        "/controllers/t/programs/BIG", content=TRIO_PROGRAM,
        headers={"content-type": "text/plain"}))
    assert r.status_code == 201, r.text
    assert r.json()["lines"] == 6000
    # the work ran beside the loop: never held for more than half of it (or 50 ms)
    assert len(gaps) >= 5 and max(gaps) < max(sum(gaps) / 2, 0.05)
    stored = await trio_api.get("/controllers/t/programs/BIG")
    assert stored.text == TRIO_PROGRAM


async def test_a_large_trio_program_with_an_error_stores_nothing(trio_api):
    bad = TRIO_PROGRAM + "\nVR(1)=(3\n"
    r = await trio_api.put("/controllers/t/programs/BAD", content=bad,
                           headers={"content-type": "text/plain"})
    assert r.status_code == 422 and r.json()["code"] == "parse_error"
    assert r.json()["line"] == 6001
    assert (await trio_api.get("/controllers/t/programs/BAD")).status_code == 404


async def test_a_large_plc_compiles_while_the_loop_serves_others(pmac_api):
    r, gaps = await _with_ticker(pmac_api.put("/controllers/p/plcs/1", json={"text": PLC_TEXT}))
    assert r.status_code == 200, r.text
    assert r.json()["lines"] >= 4000
    # the work ran beside the loop: never held for more than half of it (or 50 ms)
    assert len(gaps) >= 5 and max(gaps) < max(sum(gaps) / 2, 0.05)
