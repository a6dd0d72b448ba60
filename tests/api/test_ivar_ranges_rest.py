"""REST writes of PMAC I-variables follow the card's value rules and answer what was stored:
a limited range rolls over (TUM p243), an I41-locked set ignores the write (TSRM p57)."""

from __future__ import annotations

import pytest

pytestmark = pytest.mark.anyio


async def test_put_i3_5_answers_and_stores_1(pmac_api):
    r = await pmac_api.put("/controllers/p/variables/I3", json={"value": 5})
    assert r.status_code == 200 and r.json() == {"name": "I3", "value": 1.0}
    assert (await pmac_api.get("/controllers/p/variables/I3")).json()["value"] == 1.0


async def test_a_bulk_write_locked_by_i41_in_the_same_map_is_ignored_without_error(pmac_api):
    r = await pmac_api.put("/controllers/p/variables",
                           json={"I41": 1, "I130": 5, "I5113": 266})
    assert r.status_code == 200
    assert r.json()["values"] == {"I41": 1.0, "I130": 2000.0, "I5113": 10.0}
