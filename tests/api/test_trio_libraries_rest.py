"""BASIC libraries and the mc6xx model over REST (issue 32): a library stored with
``PUT /programs`` makes its FUNCTIONs known to programs stored afterwards, cannot be RUN (422
naming it), a call with a wrong argument count is a 422 with line and column; the mc6xx sizes
reach ``GET /variables``."""

from __future__ import annotations

import pytest
from motionsim.api.main import create_app

from tests.conftest import dummy_settings, rest_client

pytestmark = pytest.mark.anyio
T = "/controllers/t"
PLAIN = {"content-type": "text/plain"}
LIBRARY = "FUNCTION clamp(v, lo, hi AS FLOAT) AS FLOAT\n  IF v > hi THEN RETURN hi\n" \
          "  IF v < lo THEN RETURN lo\n  RETURN v\nENDFUNC\n"


@pytest.fixture
async def api():
    settings = dummy_settings(controllers=[
        {"id": "t", "kind": "trio", "clock": {"mode": "virtual"}, "config": {"model": "mc6xx"}}])
    async with rest_client(create_app(settings)) as client:
        yield client


async def test_a_library_serves_the_programs_stored_after_it(api) -> None:
    assert (await api.put(f"{T}/programs/TOOLS", content=LIBRARY, headers=PLAIN)
            ).status_code == 201
    text = "VR(65535) = clamp(120, 0, 100)\nTABLE(511999) = clamp(-5, 0, 100)\n"
    assert (await api.put(f"{T}/programs/MAIN", content=text, headers=PLAIN)).status_code == 201
    await api.post(f"{T}/programs/MAIN/run", json={"process": 22})
    await api.post(f"{T}/clock/advance", json={"seconds": 0.1})
    assert (await api.get(f"{T}/variables/VR(65535)")).json()["value"] == 100.0
    assert (await api.get(f"{T}/variables/TABLE(511999)")).json()["value"] == 0.0
    assert (await api.get(f"{T}/variables/VR(65536)")).status_code == 404


async def test_a_library_cannot_be_run_and_a_bad_call_is_refused(api) -> None:
    assert (await api.put(f"{T}/programs/TOOLS", content=LIBRARY, headers=PLAIN)
            ).status_code == 201
    r = await api.post(f"{T}/programs/TOOLS/run", json={"process": 1})
    assert r.status_code == 422 and "TOOLS is a BASIC library" in r.json()["message"]
    r = await api.put(f"{T}/programs/BAD", content="VR(0) = 1\nVR(1) = clamp(2)\n",
                      headers=PLAIN)
    assert r.status_code == 422
    body = r.json()
    assert (body["line"], body["column"], body["program"]) == (2, 1, "BAD")
    assert "CLAMP takes 3 arguments, got 1" in body["message"]
