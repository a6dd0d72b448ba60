"""Finite, documented bounds on every time and rate, strict number types, and the contract's
small print (405 carries ``Allow``).

A factor near 1e308 used to be accepted, after which that controller and ``GET /controllers``
answered 500; ``{"seconds": true}`` ran one second.
"""

from __future__ import annotations

import asyncio
import math

import pytest

from tests.conftest import rest_client

pytestmark = pytest.mark.anyio


@pytest.mark.parametrize("factor", [1e308, 1e5, 0.0, -1.0, 1e-9])
async def test_a_clock_factor_out_of_bounds_is_422_and_nothing_changes(api, factor):
    r = await api.patch("/controllers/d/clock", json={"factor": factor})
    assert (r.status_code, r.json()["field"]) == (422, "factor")
    r = await api.post("/controllers", json={"id": "x", "kind": "dummy",
                                             "clock": {"mode": "realtime", "factor": factor}})
    assert (r.status_code, r.json()["field"]) == (422, "clock.factor")
    assert [c["id"] for c in (await api.get("/controllers")).json()] == ["d"]


async def test_the_largest_factor_and_advance_allowed_keep_every_clock_finite(api):
    quiet = {"tick_s": 0}  # no ticker: a long advance is quick
    for cid, mode in (("fast", "realtime"), ("long", "virtual")):
        r = await api.post("/controllers", json={"id": cid, "kind": "dummy", "config": quiet,
                                                 "clock": {"mode": mode, "factor": 1e4}})
        assert r.status_code == 201, r.text
    assert (await api.post("/controllers/long/clock/advance",
                           json={"seconds": 1e6})).status_code == 200
    await asyncio.sleep(0.05)
    clocks = {c["id"]: c["clock"] for c in (await api.get("/controllers")).json()}
    assert clocks["long"]["t"] == 1e6
    assert 0 < clocks["fast"]["t"] < 1e6 and math.isfinite(clocks["fast"]["t"])
    assert (await api.get("/controllers/fast/clock")).json()["t"] is not None


@pytest.mark.parametrize("url, body, field", [
    ("/controllers/d/clock/advance", {"seconds": 1e7}, "seconds"),
    ("/controllers/d/clock/advance", {"seconds": True}, "seconds"),
    ("/controllers/d/clock/advance", {"seconds": "1"}, "seconds"),
    ("/controllers/d/clock/run-until", {"event": {"type": "tick"}, "timeout_s": 1e7},
     "timeout_s"),
    ("/controllers/d/clock/run-until", {"event": {"type": "tick"}, "timeout_s": False},
     "timeout_s"),
])
async def test_times_out_of_bounds_or_not_numbers_are_422_naming_the_field(api, url, body,
                                                                            field):
    r = await api.post(url, json=body)
    assert (r.status_code, r.json()["code"], r.json()["field"]) == (
        422, "validation_error", field)
    assert (await api.get("/controllers/d/clock")).json()["t"] == 0.0


async def test_a_bool_is_not_a_number_for_a_variable_or_a_rotary_size(make_app):
    settings = {"controllers": [{"id": "p", "kind": "pmac", "clock": {"mode": "virtual"}}]}
    async with rest_client(make_app(**settings)) as api:
        r = await api.put("/controllers/p/variables/P1", json={"value": True})
        assert (r.status_code, r.json()["field"]) == (422, "value")
        r = await api.put("/controllers/p/coord/1/rotary", json={"size_words": True})
        assert (r.status_code, r.json()["field"]) == (422, "size_words")
        assert (await api.get("/controllers/p/variables/P1")).json()["value"] == 0.0


async def test_openapi_documents_the_bounds(api):
    schemas = (await api.get("/openapi.json")).json()["components"]["schemas"]
    assert schemas["AdvanceIn"]["properties"]["seconds"]["maximum"] == 1e6
    assert schemas["RunUntilIn"]["properties"]["timeout_s"]["maximum"] == 1e6
    factor = schemas["ClockIn"]["properties"]["factor"]
    assert (factor["minimum"], factor["maximum"]) == (1e-3, 1e4)
    config = schemas["ControllerIn"]["properties"]["config"]["description"]
    for text in ("servo_hz: 100 <= x <= 100000 Hz", "statement_us: 0 < x <= 100000 us",
                 "vr_count: 1 <= x <= 65536", "axes: 1 <= x <= 64", "table_size"):
        assert text in config


@pytest.mark.parametrize("kind, config, field", [
    ("pmac", {"servo_hz": 1e308}, "servo_hz"), ("pmac", {"servo_hz": 10}, "servo_hz"),
    ("pmac", {"cpu_plc_statement_us": 1e9}, "cpu_plc_statement_us"),
    ("trio", {"servo_period_ms": 1e-9}, "servo_period_ms"),
    ("trio", {"statement_us": 1e300}, "statement_us"),
    ("trio", {"vr_count": 10**9}, "vr_count"), ("trio", {"axes": 100_000}, "axes"),
    ("trio", {"table_size": 10**12}, "table_size"), ("trio", {"speed": 1e300}, "speed"),
])
async def test_controller_config_out_of_bounds_is_422_naming_the_key(api, kind, config, field):
    r = await api.post("/controllers", json={"id": "x", "kind": kind,
                                             "clock": {"mode": "virtual"}, "config": config})
    assert (r.status_code, r.json()["field"]) == (422, field), r.text
    assert "x" not in [c["id"] for c in (await api.get("/controllers")).json()]


async def test_the_number_of_controllers_is_bounded(make_app):
    async with rest_client(make_app(max_controllers=3)) as api:
        for _ in range(2):
            r = await api.post("/controllers", json={"kind": "dummy",
                                                     "clock": {"mode": "virtual"}})
            assert r.status_code == 201
        r = await api.post("/controllers", json={"kind": "dummy", "clock": {"mode": "virtual"}})
        assert (r.status_code, r.json()["code"]) == (409, "conflict")
        assert "max_controllers" in r.json()["message"]
        assert len((await api.get("/controllers")).json()) == 3


async def test_a_trio_move_with_a_huge_distance_is_422(make_app):
    settings = {"controllers": [{"id": "t", "kind": "trio", "clock": {"mode": "virtual"}}]}
    async with rest_client(make_app(**settings)) as api:
        r = await api.post("/controllers/t/axes/0/moves", json={"type": "MOVE", "args": [1e300]})
        assert (r.status_code, r.json()["field"]) == (422, "args.0")
        assert (await api.get("/controllers/t/axes/0")).json()["mtype"] == 0


async def test_405_carries_allow_with_every_method_of_the_path(api):
    r = await api.put("/controllers/d")
    assert r.status_code == 405
    assert r.json()["code"] == "method_not_allowed"
    assert r.headers["allow"] == "GET, DELETE"
    assert "allowed: GET, DELETE" in r.json()["message"]
    r = await api.post("/controllers/d/clock")
    assert r.headers["allow"] == "GET, PATCH"
