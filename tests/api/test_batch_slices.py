"""A rotary batch is bounded and parsed in slices (issue 23, item 1).

``lines`` holds at most ``MAX_BATCH_LINES`` (422 naming ``lines`` and the limit, nothing
stored); a batch of long expression lines — seconds of parsing — lets ``/health`` and another
controller be served while it is parsed, and is then stored all or nothing as before.
"""

from __future__ import annotations

import asyncio

import pytest
from motionsim.api.line_slices import MAX_BATCH_LINES

from tests.api.loop_gaps import assert_served_beside, with_ticker

pytestmark = pytest.mark.anyio

LONG = "X{i} " + " ".join(f"P{j}=P{j}+{{i}}" for j in range(20))


async def _rotary(api, words: int = 65_536) -> None:
    r = await api.put("/controllers/p/coord/1/rotary", json={"size_words": words})
    assert r.status_code == 200, r.text


async def test_a_batch_over_the_line_limit_is_422_naming_lines_and_the_limit(pmac_api):
    await _rotary(pmac_api)
    r = await pmac_api.post("/controllers/p/coord/1/rotary/lines",
                            json={"lines": ["X1"] * (MAX_BATCH_LINES + 1)})
    assert r.status_code == 422
    body = r.json()
    assert body["field"] == "lines" and str(MAX_BATCH_LINES) in body["message"]
    rotary = (await pmac_api.get("/controllers/p/coord/1")).json()["rotary"]
    assert rotary["used_words"] == 0


async def test_a_batch_at_the_limit_is_stored(pmac_api):
    await _rotary(pmac_api)
    r = await pmac_api.post("/controllers/p/coord/1/rotary/lines",
                            json={"lines": [f"X{i}" for i in range(MAX_BATCH_LINES)]})
    assert r.status_code == 200, r.text
    assert r.json()["stored"] == MAX_BATCH_LINES


async def test_health_is_served_while_a_long_batch_is_parsed(pmac_api):
    """A long parse (800 lines of 20 expressions each): the loop is never held for more than
    a fraction of it — a ticker keeps ticking and its longest gap stays far below it."""
    await _rotary(pmac_api)
    lines = [LONG.format(i=i) for i in range(800)]

    async def store_while_health_is_served():
        store = asyncio.ensure_future(pmac_api.post("/controllers/p/coord/1/rotary/lines",
                                                    json={"lines": lines}))
        await asyncio.sleep(0.05)
        health = await pmac_api.get("/health")
        assert health.status_code == 200
        return await store

    r, gaps = await with_ticker(store_while_health_is_served())
    assert r.status_code == 200 and r.json()["stored"] == 800
    assert_served_beside(gaps)


async def test_a_bad_line_in_a_sliced_batch_is_reported_with_its_index(pmac_api):
    await _rotary(pmac_api)
    lines = [LONG.format(i=i) for i in range(50)]
    lines[37] = "X1 P1=(3"
    r = await pmac_api.post("/controllers/p/coord/1/rotary/lines", json={"lines": lines})
    assert r.status_code == 422
    assert r.json()["code"] == "parse_error" and r.json()["index"] == 37
    rotary = (await pmac_api.get("/controllers/p/coord/1")).json()["rotary"]
    assert rotary["used_words"] == 0


async def test_a_refused_sliced_batch_leaves_nothing_remembered(pmac_api):
    """A batch parsed in slices and then refused (409 ``buffer_full``) changes nothing: not
    the buffer, and not the controller's memo of compiled lines, which holds stored lines
    only (the compiled lines are handed to ``load_lines``, not put in the memo first)."""
    from motionsim.sim.pmac.controller import PmacController

    await _rotary(pmac_api, words=100)
    lines = ["Y" + LONG.format(i=900 + i)[1:] for i in range(40)]  # 21 words each: 840 > 100
    r = await pmac_api.post("/controllers/p/coord/1/rotary/lines", json={"lines": lines})
    assert r.status_code == 409 and r.json()["code"] == "buffer_full", r.text
    assert not any(PmacController.line_compiled(text) for text in lines)
    rotary = (await pmac_api.get("/controllers/p/coord/1")).json()["rotary"]
    assert rotary["used_words"] == 0
    stored = await pmac_api.post("/controllers/p/coord/1/rotary/lines", json={"lines": lines[:4]})
    assert stored.status_code == 200 and stored.json()["stored"] == 4
    assert all(PmacController.line_compiled(text) for text in lines[:4])
