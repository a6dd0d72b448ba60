"""``POST .../rotary/lines`` with ``first_seq`` over REST: the 409 body names the expected seq."""

from __future__ import annotations

import pytest

pytestmark = pytest.mark.anyio

LINES = "/controllers/p/coord/1/rotary/lines"


async def test_a_gap_is_409_conflict_with_expected_seq_and_nothing_stored(pmac_api):
    await pmac_api.put("/controllers/p/coord/1/rotary", json={"size_words": 600})
    await pmac_api.post(LINES, json={"lines": ["X1", "X2"], "first_seq": 1})
    before = (await pmac_api.get("/controllers/p/events")).json()["next"]
    r = await pmac_api.post(LINES, json={"lines": ["X9"], "first_seq": 7})
    assert r.status_code == 409
    body = r.json()
    assert (body["code"], body["reason"], body["expected_seq"], body["first_seq"]) == (
        "conflict", "gap", 3, 7)
    assert (await pmac_api.get("/controllers/p/events")).json()["next"] == before
    r = await pmac_api.post(LINES, json={"lines": ["X3"], "first_seq": 3})
    assert (r.status_code, r.json()["stored"]) == (200, 1)


async def test_a_huge_first_seq_is_409_not_accepted_and_dropped(pmac_api):
    await pmac_api.put("/controllers/p/coord/1/rotary", json={"size_words": 600})
    r = await pmac_api.post(LINES, json={"lines": ["X1"], "first_seq": 2**63})
    assert (r.status_code, r.json()["reason"]) == (409, "out_of_range")
    r = await pmac_api.post(LINES, json={"lines": ["X1"], "first_seq": 1})
    assert (r.status_code, r.json()["stored"]) == (200, 1)


async def test_rest_abort_restarts_the_numbering(pmac_api):
    await pmac_api.put("/controllers/p/coord/1/rotary", json={"size_words": 600})
    await pmac_api.post(LINES, json={"lines": ["X1", "X2"], "first_seq": 1})
    await pmac_api.post("/controllers/p/coord/1/abort")
    r = await pmac_api.post(LINES, json={"lines": ["X5"], "first_seq": 1})
    assert (r.status_code, r.json()["stored"]) == (200, 1)
