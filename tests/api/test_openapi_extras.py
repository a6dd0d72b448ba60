"""``/openapi.json`` publishes the event ``type`` enum, Trio ``process`` 1..N by model and
integer bounds as integers — the seed's ``2**63 - 1`` exactly (issue 33 item 7)."""

from __future__ import annotations

import pytest
from motionsim.sim.events import EVENT_FIELDS
from motionsim.sim.trio.card.models import MODELS

pytestmark = pytest.mark.anyio


async def _spec(api) -> dict:
    return (await api.get("/openapi.json")).json()


def _bounds(node, out):
    if isinstance(node, dict):
        if node.get("type") == "integer":
            out += [node[b] for b in ("minimum", "maximum") if b in node]
        for v in node.values():
            _bounds(v, out)
    elif isinstance(node, list):
        for v in node:
            _bounds(v, out)
    return out


async def test_event_types_are_an_enum_on_events_and_the_events_query(api) -> None:
    spec = await _spec(api)
    schemas = spec["components"]["schemas"]
    enum = schemas["EventOut"]["properties"]["type"]["enum"]
    assert set(EVENT_FIELDS) <= set(enum) and enum == sorted(enum)
    (param,) = [p for p in spec["paths"]["/controllers/{controller_id}/events"]["get"]
                ["parameters"] if p["name"] == "type"]
    items = [s for s in param["schema"]["anyOf"] if s.get("type") == "array"][0]["items"]
    assert "breq" in items["enum"] and "program_send" in items["enum"]
    # what the server accepts is what it publishes
    assert (await api.get("/controllers/d/events", params={"type": items["enum"][0]})
            ).status_code == 200


async def test_trio_process_maximum_by_model(api) -> None:
    spec = await _spec(api)
    process = spec["components"]["schemas"]["RunIn"]["properties"]["process"]
    assert process["x-maximum-by-model"] == {n: m.processes for n, m in MODELS.items()}
    assert "mc4xx 22" in process["description"]


async def test_integer_bounds_are_integers_and_the_seed_bound_is_exact(api) -> None:
    spec = await _spec(api)
    bounds = _bounds(spec, [])
    assert bounds and all(isinstance(b, int) for b in bounds)
    seed = spec["components"]["schemas"]["BreqLost"]["properties"]["seed"]
    assert (seed["minimum"], seed["maximum"]) == (0, 2**63 - 1)
