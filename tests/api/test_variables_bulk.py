"""PUT /controllers/{id}/variables: several variables in one request, all or nothing."""

from __future__ import annotations

import pytest

pytestmark = pytest.mark.anyio


async def test_a_map_of_pmac_variables_is_written_in_one_request(pmac_api):
    r = await pmac_api.put("/controllers/p/variables", json={"i16": 5, "I17": 10, "P1": 2.5})
    assert r.status_code == 200
    assert r.json() == {"values": {"I16": 5.0, "I17": 10.0, "P1": 2.5}}
    for name, value in (("I16", 5.0), ("I17", 10.0), ("P1", 2.5)):
        got = (await pmac_api.get(f"/controllers/p/variables/{name}")).json()
        assert got == {"name": name, "value": value}


async def test_m_variable_writes_are_events_in_the_order_given(pmac_api):
    await pmac_api.put("/controllers/p/variables", json={"M2": 1, "M1": 1, "M3": 0})
    ev = (await pmac_api.get("/controllers/p/events", params={"type": "mvar"})).json()["events"]
    assert [(e["name"], e["value"], e["sync"]) for e in ev] == [
        ("M2", 1.0, False), ("M1", 1.0, False), ("M3", 0.0, False)]


async def test_one_unknown_name_is_422_naming_it_and_nothing_is_written(pmac_api):
    before = (await pmac_api.get("/controllers/p/events")).json()["next"]
    r = await pmac_api.put("/controllers/p/variables",
                           json={"I16": 7, "M1": 1, "X99": 1, "P2": 3})
    assert r.status_code == 422
    body = r.json()
    assert body["code"] == "validation_error" and body["field"] == "X99"
    assert "X99" in body["message"]
    assert (await pmac_api.get("/controllers/p/variables/I16")).json()["value"] != 7
    assert (await pmac_api.get("/controllers/p/variables/P2")).json()["value"] == 0
    assert (await pmac_api.get("/controllers/p/events",
                               params={"since": before})).json()["events"] == []


@pytest.mark.parametrize("body", [{}, {"I16": "five"}, {"I16": None}, [1, 2], {"I16": True}])
async def test_a_bad_body_is_422_and_nothing_changes(pmac_api, body):
    before = (await pmac_api.get("/controllers/p/variables/I16")).json()
    r = await pmac_api.put("/controllers/p/variables", json=body)
    assert r.status_code == 422
    assert r.json()["code"] == "validation_error"
    assert (await pmac_api.get("/controllers/p/variables/I16")).json() == before


async def test_trio_vr_values_in_one_request(trio_api):
    r = await trio_api.put("/controllers/t/variables", json={"VR(1)": 10, "VR(101)": 200})
    assert r.status_code == 200
    assert r.json()["values"] == {"VR(1)": 10.0, "VR(101)": 200.0}
    got = (await trio_api.get("/controllers/t/variables/VR%28101%29")).json()
    assert got["value"] == 200.0
    r = await trio_api.put("/controllers/t/variables", json={"VR(2)": 1, "VR(x)": 1})
    assert r.status_code == 422 and r.json()["field"] == "VR(x)"
    assert (await trio_api.get("/controllers/t/variables/VR%282%29")).json()["value"] == 0
