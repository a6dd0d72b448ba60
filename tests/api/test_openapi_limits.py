"""Every limit the server enforces appears in ``/openapi.json`` (issue 23, item 5).

The fields schemathesis found enforced but unpublished: Trio ``process`` numbers, rotary
``first_seq`` and line length, program names and text size, bulk variable names, event
``type`` (query and run-until), controller ``kind``, coordinate-system / PLC / axis numbers.
"""

from __future__ import annotations

import pytest

pytestmark = pytest.mark.anyio

P = "/controllers/{controller_id}"


async def _spec(api) -> dict:
    return (await api.get("/openapi.json")).json()


def _resolve(spec: dict, schema: dict) -> dict:
    while "$ref" in schema:
        schema = spec["components"]["schemas"][schema["$ref"].split("/")[-1]]
    return schema


def _body(spec: dict, path: str, method: str) -> dict:
    content = spec["paths"][path][method]["requestBody"]["content"]
    return _resolve(spec, _branch(next(iter(content.values()))["schema"]))


def _param(spec: dict, path: str, method: str, name: str) -> dict:
    (param,) = [p for p in spec["paths"][path][method]["parameters"] if p["name"] == name]
    return param["schema"]


def _branch(schema: dict) -> dict:
    """The non-null branch of ``X | None``."""
    for sub in schema.get("anyOf", [schema]):
        if sub.get("type") != "null":
            return sub
    raise AssertionError(schema)


async def test_trio_process_numbers_are_bounded(trio_api):
    spec = await _spec(trio_api)
    run = _branch(_body(spec, P + "/programs/{name}/run", "post")["properties"]["process"])
    assert (run["minimum"], run["maximum"]) == (1, 32)
    move = _branch(_body(spec, P + "/axes/{axis}/moves", "post")["properties"]["process"])
    assert (move["minimum"], move["maximum"]) == (0, 32)
    stop = _param(spec, P + "/processes/{process}/stop", "post", "process")
    assert (stop["minimum"], stop["maximum"]) == (1, 32)
    r = await trio_api.post("/controllers/t/programs/X/run", json={"process": 33})
    assert r.status_code == 422 and r.json()["field"] == "process"


async def test_rotary_batches_publish_first_seq_lines_and_line_length(pmac_api):
    spec = await _spec(pmac_api)
    body = _body(spec, P + "/coord/{cs}/rotary/lines", "post")
    first_seq = _branch(body["properties"]["first_seq"])
    assert (first_seq["minimum"], first_seq["maximum"]) == (0, 2**53 - 1)
    lines = body["properties"]["lines"]
    assert lines["maxItems"] == 1024 and lines["items"]["maxLength"] == 255
    cs = _param(spec, P + "/coord/{cs}", "get", "cs")
    assert (cs["minimum"], cs["maximum"]) == (1, 16)


async def test_program_names_and_text_size_are_published(trio_api):
    spec = await _spec(trio_api)
    name = _param(spec, P + "/programs/{name}", "put", "name")
    assert name["pattern"] == "^[A-Za-z_][A-Za-z0-9_]*$" and name["maxLength"] == 32
    text = spec["paths"][P + "/programs/{name}"]["put"]["requestBody"]["content"]["text/plain"]
    assert text["schema"]["maxLength"] == 1_000_000
    r = await trio_api.put("/controllers/t/programs/9BAD", content="PRINT 1",
                           headers={"content-type": "text/plain"})
    assert r.status_code == 422 and r.json()["field"] == "name"


async def test_variable_names_event_types_kind_plc_and_axis_numbers_are_bounded(pmac_api):
    spec = await _spec(pmac_api)
    names = _body(spec, P + "/variables", "put")["propertyNames"]
    assert (names["minLength"], names["maxLength"]) == (1, 64)
    types = _branch(_param(spec, P + "/events", "get", "type"))
    assert types["maxItems"] == 64 and types["items"]["maxLength"] == 64
    event = _resolve(spec, _body(spec, P + "/clock/run-until", "post")["properties"]["event"])
    assert event["properties"]["type"]["maxLength"] == 64
    kind = _body(spec, "/controllers", "post")["properties"]["kind"]
    assert (kind["minLength"], kind["maxLength"]) == (1, 64)
    plc = _param(spec, P + "/plcs/{n}", "get", "n")
    assert (plc["minimum"], plc["maximum"]) == (0, 31)
    axis = _param(spec, P + "/axes/{axis}", "get", "axis")
    assert (axis["minimum"], axis["maximum"]) == (0, 63)
