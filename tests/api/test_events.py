"""GET /controllers/{id}/events: paging by seq, type filter, limit, gaps."""

from __future__ import annotations

import pytest
from motionsim.app.settings import Settings

pytestmark = pytest.mark.anyio


async def _tick(api, seconds):
    await api.post("/controllers/d/clock/advance", json={"seconds": seconds})


async def test_events_have_seq_t_type_controller_and_fields(api):
    await _tick(api, 0.01)
    r = await api.get("/controllers/d/events")
    assert r.status_code == 200
    body = r.json()
    assert body == {"epoch": body["epoch"], "events": [{
        "seq": 1, "t": pytest.approx(0.01), "type": "tick", "controller": "d", "n": 1}], "next": 1}
    assert isinstance(body["epoch"], str) and body["epoch"]


async def test_since_returns_only_newer_events_and_next_continues(api):
    await _tick(api, 0.1)
    page = (await api.get("/controllers/d/events", params={"since": 3, "limit": 4})).json()
    assert [e["seq"] for e in page["events"]] == [4, 5, 6, 7]
    assert page["next"] == 7
    page = (await api.get("/controllers/d/events", params={"since": page["next"]})).json()
    assert [e["seq"] for e in page["events"]] == [8, 9, 10]
    page = (await api.get("/controllers/d/events", params={"since": page["next"]})).json()
    assert page == {"epoch": page["epoch"], "events": [], "next": 10}


async def test_default_limit_is_1000(api):
    await _tick(api, 12.0)
    page = (await api.get("/controllers/d/events")).json()
    assert len(page["events"]) == 1000
    assert page["next"] == 1000


async def test_type_filter_is_repeatable(api):
    await _tick(api, 0.02)
    await api.put("/controllers/d/variables/V1", json={"value": 1})
    await api.post("/controllers/d/terminal", json={"command": "PING x"})
    r = await api.get("/controllers/d/events", params=[("type", "var"), ("type", "ping")])
    assert [(e["seq"], e["type"]) for e in r.json()["events"]] == [(3, "var"), (4, "ping")]
    assert r.json()["next"] == 4


async def test_type_filter_next_skips_past_unmatched_events(api):
    await _tick(api, 0.05)
    r = await api.get("/controllers/d/events", params={"type": "var"})
    assert r.json() == {"epoch": r.json()["epoch"], "events": [], "next": 5}


@pytest.mark.parametrize("params, field", [({"since": -1}, "since"), ({"limit": 0}, "limit"),
                                           ({"limit": "many"}, "limit")])
async def test_bad_query_is_422_naming_the_field(api, params, field):
    r = await api.get("/controllers/d/events", params=params)
    assert r.status_code == 422
    assert r.json()["field"] == field


async def test_events_dropped_from_the_ring_are_reported_as_a_gap(make_app):
    import httpx
    app = make_app()
    handle = app.state.registry.get("d")
    assert handle.controller.log.capacity == 100_000  # the service's ring
    for i in range(100_010):
        handle.controller.log.emit("fill", i=i)
    async with httpx.AsyncClient(transport=httpx.ASGITransport(app=app),
                                 base_url="http://127.0.0.1") as c:
        page = (await c.get("/controllers/d/events", params={"since": 2, "limit": 2})).json()
    assert page["gap"] == {"type": "gap", "from": 3, "to": 10}
    assert [e["seq"] for e in page["events"]] == [11, 12]
    assert page["next"] == 12


def test_log_capacity_below_100000_is_rejected():
    with pytest.raises(ValueError, match="log_capacity"):
        Settings(log_capacity=10)
