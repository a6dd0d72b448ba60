"""A page of 100 000 events is encoded in slices (issue 23, item 1): seconds of JSON
encoding never hold the event loop in one go, and the page is what it was — every event in
``EventOut`` form (``t`` a float), ``next`` after the last one."""

from __future__ import annotations

import asyncio
import gc

import pytest

pytestmark = pytest.mark.anyio


async def test_a_page_of_100000_events_lets_the_loop_run_while_it_is_encoded(api):
    """The dummy ticker emits a ``tick`` every 10 ms: 995 simulated s hold 99 500."""
    assert (await api.post("/controllers/d/clock/advance", json={"seconds": 995})).is_success
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
    gc.freeze()  # the test process's own heap is not what is measured
    ticking = asyncio.ensure_future(ticker())
    try:
        r = await api.get("/controllers/d/events", params={"limit": 100000})
    finally:
        ticking.cancel()
        gc.unfreeze()
    page = r.json()
    first, last = page["events"][0], page["events"][-1]
    assert r.status_code == 200 and len(page["events"]) > 99000
    assert list(first)[:4] == ["seq", "t", "type", "controller"]
    assert first["seq"] == 1 and isinstance(first["t"], float) and first["controller"] == "d"
    assert page["next"] == last["seq"] == len(page["events"])
    # the work ran beside the loop: never held for more than half of it (or 50 ms)
    assert len(gaps) >= 5 and max(gaps) < max(sum(gaps) / 2, 0.05)
