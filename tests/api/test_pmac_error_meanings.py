"""ERRnnn keeps its wire form; REST bodies add the Turbo SRM meaning (issue 10 item 4)."""

from __future__ import annotations

import pytest

pytestmark = pytest.mark.anyio

BASE = "/controllers/p"


async def _term(api, cmd: str) -> dict:
    r = await api.post(f"{BASE}/terminal", json={"command": cmd})
    assert r.status_code == 200
    return r.json()


async def test_a_success_body_stays_the_three_fields(pmac_api):
    assert await _term(pmac_api, "I16") == {"reply": "5", "error": None, "pending": False}


async def test_err003_carries_the_srm_meaning_and_where(pmac_api):
    body = await _term(pmac_api, "I16 )")
    assert (body["reply"], body["error"]) == ("5", "ERR003")
    assert body["error_meaning"] == "unrecognized command or invalid data (syntax error)"
    assert body["not_simulated"] is False and "column 5" in body["detail"]


async def test_err005_meaning(pmac_api):
    body = await _term(pmac_api, "X1000")
    assert body["error"] == "ERR005"
    assert body["error_meaning"] == "command allowed only with a buffer open"


async def test_a_valid_but_not_simulated_command_says_so(pmac_api):
    body = await _term(pmac_api, "PASSWORD=SECRET")
    assert body["error"] == "ERR003"
    assert body["not_simulated"] is True
    assert "not simulate" in body["detail"] and "PASSWORD" in body["detail"]


async def test_a_resource_error_body_has_pmac_meaning(pmac_api):
    await pmac_api.put(f"{BASE}/coord/1/rotary", json={"size_words": 100})
    r = await pmac_api.put(f"{BASE}/coord/2/rotary", json={"size_words": 100})
    assert r.status_code == 409
    body = r.json()
    assert body["pmac_error"] == "ERR003"
    assert body["pmac_meaning"] == "unrecognized command or invalid data (syntax error)"
