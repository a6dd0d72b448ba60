"""A large JSON body is decoded once, beside the event loop (issue 23, item 1).

The body guard decodes every JSON body to check it — a large one in the worker thread — and
the route validates what it decoded: the body is never decoded again on the event loop
(70 ms for a body at the 8-MiB limit). The answers are those of before: the batch over the
line limit is 422 naming ``lines`` and the limit, a malformed body is 422 ``validation_error``
naming ``body`` with the position of the fault, and a small body is served as always.
"""

from __future__ import annotations

import json
import threading

import pytest

pytestmark = pytest.mark.anyio

LINES = "/controllers/p/coord/1/rotary/lines"
JSON = {"content-type": "application/json"}


@pytest.fixture
def loop_decodes(monkeypatch) -> list[int]:
    """Sizes of the bodies ``json.loads`` decodes on the event loop's thread."""
    sizes: list[int] = []
    loads = json.loads
    loop_thread = threading.get_ident()

    def spied(text, *args, **kwargs):
        if threading.get_ident() == loop_thread:
            sizes.append(len(text))
        return loads(text, *args, **kwargs)

    monkeypatch.setattr(json, "loads", spied)
    return sizes


async def test_a_batch_at_the_body_limit_is_refused_without_decoding_it_on_the_loop(
        pmac_api, loop_decodes):
    body = json.dumps({"lines": ["X1"] * 1_300_000}).encode()  # 7.8 MB, under 8 MiB
    assert (await pmac_api.put("/controllers/p/coord/1/rotary",
                               json={"size_words": 1000})).status_code == 200
    r = await pmac_api.post(LINES, content=body, headers=JSON)
    assert r.status_code == 422, r.text
    assert r.json()["field"] == "lines" and "1024" in r.json()["message"]
    assert not [n for n in loop_decodes if n > 64 * 1024], loop_decodes
    assert (await pmac_api.get("/controllers/p/coord/1")).json()["rotary"]["used_words"] == 0


async def test_a_large_malformed_body_is_422_at_its_fault_without_decoding_it_on_the_loop(
        pmac_api, loop_decodes):
    body = b'{"lines": [' + b'"X1", ' * 20_000 + b'"X1" "X2"]}'
    r = await pmac_api.post(LINES, content=body, headers=JSON)
    assert r.status_code == 422
    error = r.json()
    assert error["code"] == "validation_error" and error["field"] == "body"
    assert error["message"].startswith("malformed JSON body: Expecting ','")
    assert error["errors"][0]["loc"] == ["body", body.index(b'"X2"')]
    assert not [n for n in loop_decodes if n > 64 * 1024], loop_decodes


async def test_a_small_body_is_decoded_once(pmac_api, loop_decodes):
    assert (await pmac_api.put("/controllers/p/coord/1/rotary",
                               json={"size_words": 1000})).status_code == 200
    body = json.dumps({"lines": ["X1", "X2"], "first_seq": 0})
    r = await pmac_api.post(LINES, content=body, headers=JSON)
    assert r.status_code == 200 and r.json()["stored"] == 2
    assert loop_decodes.count(len(body)) == 1, loop_decodes  # the guard's decode, used twice


def test_every_route_reads_the_decoded_body():
    """A router added later reads it too (its ``route_class``): else it decodes again."""
    from fastapi.routing import APIRoute
    from motionsim.api.decoded_json import DecodedJsonRoute
    from motionsim.api.main import discover_routers

    routes = [r for _, router in discover_routers() for r in router.routes]
    assert routes and all(isinstance(r, DecodedJsonRoute) for r in routes
                          if isinstance(r, APIRoute))
