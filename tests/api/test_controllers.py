"""/health and /controllers: list, create, inspect, delete, reset — and their errors."""

from __future__ import annotations

import asyncio
import time

import pytest

pytestmark = pytest.mark.anyio


async def test_health_is_ok(api):
    r = await api.get("/health")
    assert r.status_code == 200
    assert r.json() == {"status": "ok"}


async def test_health_is_503_until_the_listeners_accept(api):
    api.app.state.ready = False
    r = await api.get("/health")
    assert r.status_code == 503
    assert r.json() == {"status": "starting"}


async def test_list_controllers_shows_id_kind_clock_and_status(api):
    r = await api.get("/controllers")
    assert r.status_code == 200
    assert r.json() == [{"id": "d", "kind": "dummy", "ticks": 0,
                         "clock": {"mode": "virtual", "factor": 1.0, "paused": False, "t": 0.0}}]


async def test_get_one_controller_merges_the_kind_status(api):
    await api.post("/controllers/d/clock/advance", json={"seconds": 0.05})
    r = await api.get("/controllers/d")
    assert r.status_code == 200
    body = r.json()
    assert body["ticks"] == 5
    assert body["clock"]["t"] == pytest.approx(0.05)


async def test_create_controller_returns_201_and_it_is_listed(api):
    r = await api.post("/controllers", json={"id": "d2", "kind": "dummy",
                                             "clock": {"mode": "virtual"},
                                             "config": {"tick_s": 0.5}})
    assert r.status_code == 201
    assert r.json()["id"] == "d2"
    assert r.json()["clock"]["mode"] == "virtual"
    ids = [c["id"] for c in (await api.get("/controllers")).json()]
    assert ids == ["d", "d2"]


async def test_create_controller_without_id_numbers_it_after_its_kind(api):
    r = await api.post("/controllers", json={"kind": "dummy", "clock": {"mode": "virtual"}})
    assert r.status_code == 201
    assert r.json()["id"] == "dummy1"


async def test_create_realtime_controller_advances_with_wall_time(api):
    before = time.monotonic()  # the clock starts somewhere inside the POST
    r = await api.post("/controllers", json={"id": "rt", "kind": "dummy",
                                             "clock": {"mode": "realtime", "factor": 10}})
    created_within = time.monotonic() - before
    assert r.status_code == 201
    clock = r.json()["clock"]
    assert {k: clock[k] for k in ("mode", "factor", "paused")} == {
        "mode": "realtime", "factor": 10.0, "paused": False}
    assert 0.0 <= clock["t"] <= 10 * created_within  # ten simulated s per wall s, from 0
    assert (clock["behind"], clock["slipped_s"]) == (False, 0.0) and clock["lag_s"] < 0.1
    await asyncio.sleep(0.3)
    clock = (await api.get("/controllers/rt/clock")).json()
    since_before = time.monotonic() - before
    # ten simulated seconds per wall second: at least the 0.3 s slept (less any time a loaded
    # machine made the clock give up, reported as slipped_s), at most what passed since the
    # POST began (however long a loaded machine took to answer it)
    t = clock["t"]
    assert t + clock.get("slipped_s", 0.0) + 0.05 >= 10 * 0.3
    assert t <= 10 * since_before


async def test_create_with_unknown_kind_is_422_and_creates_nothing(api):
    r = await api.post("/controllers", json={"id": "x", "kind": "nope"})
    assert r.status_code == 422
    assert r.json()["code"] == "validation_error"
    assert r.json()["field"] == "kind"
    assert "nope" in r.json()["message"]
    assert (await api.get("/controllers/x")).status_code == 404


async def test_create_with_config_key_the_kind_rejects_is_422(api):
    r = await api.post("/controllers", json={"id": "x", "kind": "dummy", "config": {"i99": 1}})
    assert r.status_code == 422
    assert r.json()["field"] == "config.i99"
    assert (await api.get("/controllers/x")).status_code == 404


async def test_create_with_taken_id_is_409_conflict(api):
    r = await api.post("/controllers", json={"id": "d", "kind": "dummy"})
    assert r.status_code == 409
    assert r.json()["code"] == "conflict"


@pytest.mark.parametrize("body, field", [
    ({"kind": "dummy", "id": "bad id"}, "id"),
    ({"kind": "dummy", "clock": {"mode": "sometimes"}}, "clock.mode"),
    ({"kind": "dummy", "clock": {"mode": "realtime", "factor": 0}}, "clock.factor"),
    ({"kind": "dummy", "clock": {"mode": "realtime", "factor": -1}}, "clock.factor"),
    ({"id": "x"}, "kind"),
    ({"kind": "dummy", "colour": "red"}, "colour"),
])
async def test_create_with_bad_field_is_422_naming_it(api, body, field):
    r = await api.post("/controllers", json=body)
    assert r.status_code == 422
    assert r.json()["code"] == "validation_error"
    assert r.json()["field"] == field
    assert len((await api.get("/controllers")).json()) == 1


async def test_malformed_json_body_is_422(api):
    r = await api.post("/controllers", content=b'{"kind": "dummy",',
                       headers={"content-type": "application/json"})
    assert r.status_code == 422
    assert r.json()["code"] == "validation_error"
    assert "JSON" in r.json()["message"]


async def test_unknown_controller_is_404_with_json_body(api):
    for method, path in [("GET", "/controllers/zz"), ("DELETE", "/controllers/zz"),
                         ("POST", "/controllers/zz/reset"), ("GET", "/controllers/zz/clock"),
                         ("GET", "/controllers/zz/events"), ("GET", "/controllers/zz/terminal"),
                         ("GET", "/controllers/zz/variables/V1")]:
        r = await api.request(method, path)
        assert r.status_code == 404, path
        assert r.json()["code"] == "not_found"
        assert "zz" in r.json()["message"]


async def test_delete_controller_removes_it(api):
    r = await api.delete("/controllers/d")
    assert r.status_code == 204
    assert (await api.get("/controllers/d")).status_code == 404
    assert (await api.get("/controllers")).json() == []


async def test_reset_is_the_power_cycle_and_time_goes_on(api):
    await api.put("/controllers/d/variables/V1", json={"value": 3})
    await api.post("/controllers/d/clock/advance", json={"seconds": 0.02})
    r = await api.post("/controllers/d/reset")
    assert r.status_code == 200
    assert r.json()["clock"]["t"] == pytest.approx(0.02)
    assert (await api.get("/controllers/d/variables/V1")).json()["value"] == 0.0
    ev = (await api.get("/controllers/d/events", params={"type": "reset"})).json()["events"]
    assert [(e["type"], e["t"]) for e in ev] == [("reset", pytest.approx(0.02))]


async def test_unknown_path_is_404_json(api):
    r = await api.get("/nowhere")
    assert r.status_code == 404
    assert r.json()["code"] == "not_found"


async def test_openapi_lists_every_body_as_a_model(api):
    spec = (await api.get("/openapi.json")).json()
    schemas = spec["components"]["schemas"]
    for name in ["ControllerIn", "ControllerOut", "ClockOut", "ClockPatch", "AdvanceIn",
                 "RunUntilIn", "RunUntilOut", "EventsPage", "EventOut", "TerminalIn",
                 "TerminalOut", "TerminalState", "VariableIn", "VariableOut", "ErrorBody",
                 "Health"]:
        assert name in schemas, name
    post = spec["paths"]["/controllers"]["post"]
    assert post["responses"]["422"]["content"]["application/json"]["schema"]["$ref"].endswith(
        "/ErrorBody")


async def test_an_unexpected_exception_is_a_500_json_body(make_app):
    import httpx

    app = make_app()
    handle = app.state.registry.get("d")

    def broken(*_a, **_k):
        raise RuntimeError("boom")

    handle.controller.get_variable = broken
    transport = httpx.ASGITransport(app=app, raise_app_exceptions=False)
    async with httpx.AsyncClient(transport=transport, base_url="http://127.0.0.1") as c:
        r = await c.get("/controllers/d/variables/V1")
    assert r.status_code == 500
    assert r.json() == {"code": "internal_error", "message": "internal error: RuntimeError: boom"}


async def test_root_says_what_this_is_and_where_the_docs_are(api):
    r = await api.get("/")
    assert r.status_code == 200
    body = r.json()
    assert (body["service"], body["docs"], body["controllers"]) == ("motionsim", "/docs", ["d"])
    assert (await api.get("/docs")).status_code == 200
