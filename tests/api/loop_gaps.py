"""Measuring how long a request holds the event loop: a ticker sleeping 5 ms records the gaps
between its wake-ups while the request runs (issue 23, item 1)."""

from __future__ import annotations

import asyncio
import gc
from collections.abc import Awaitable
from typing import TypeVar

T = TypeVar("T")


async def with_ticker(call: Awaitable[T]) -> tuple[T, list[float]]:
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


def assert_served_beside(gaps: list[float]) -> None:
    """The work ran beside the loop: it kept ticking and was never held for more than half of
    the work's time (or 50 ms) — work done on the loop in one go holds it for all of it."""
    assert len(gaps) >= 5, gaps
    assert max(gaps) < max(sum(gaps) / 2, 0.05), (max(gaps), sum(gaps))
