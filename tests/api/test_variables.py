"""GET/PUT /controllers/{id}/variables/{name}: generic through the kind."""

from __future__ import annotations

import pytest

pytestmark = pytest.mark.anyio


async def test_put_then_get_a_variable(api):
    r = await api.put("/controllers/d/variables/v3", json={"value": 2.5})
    assert r.status_code == 200
    assert r.json() == {"name": "V3", "value": 2.5}
    assert (await api.get("/controllers/d/variables/V3")).json() == {"name": "V3", "value": 2.5}


async def test_a_write_acts_at_the_current_instant_and_does_not_move_the_clock(api):
    await api.post("/controllers/d/clock/advance", json={"seconds": 0.015})
    await api.put("/controllers/d/variables/V1", json={"value": 7})
    ev = (await api.get("/controllers/d/events", params={"type": "var"})).json()["events"]
    assert [(e["name"], e["value"], e["t"]) for e in ev] == [("V1", 7.0, pytest.approx(0.015))]
    assert (await api.get("/controllers/d/clock")).json()["t"] == pytest.approx(0.015)


async def test_unknown_variable_is_404(api):
    r = await api.get("/controllers/d/variables/Q99")
    assert r.status_code == 404
    assert r.json()["code"] == "not_found"


async def test_url_encoded_name_reaches_the_kind(api):
    r = await api.get("/controllers/d/variables/VR%285%29")
    assert r.status_code == 404
    assert "VR(5)" in r.json()["message"]


@pytest.mark.parametrize("body", [{}, {"value": "x"}, {"value": None}])
async def test_bad_value_is_422_and_nothing_changes(api, body):
    r = await api.put("/controllers/d/variables/V1", json=body)
    assert r.status_code == 422
    assert r.json()["field"] == "value"
    assert (await api.get("/controllers/d/variables/V1")).json()["value"] == 0.0
