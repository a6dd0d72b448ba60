"""Large program stores do not hold the event loop (issue 23, item 1).

A Trio program of hundreds of kilobytes or a PLC of thousands of lines takes seconds to
compile; it is compiled in the service's worker thread while ``/health`` and every other
client are served, then stored all or nothing as before (a parse error: 422, nothing stored).
"""

from __future__ import annotations

import pytest

from tests.api.loop_gaps import assert_served_beside, with_ticker

pytestmark = pytest.mark.anyio


TRIO_PROGRAM = "\n".join(f"VR({i % 500})=VR({i % 500})+{i}*2" for i in range(6000))
PLC_TEXT = "\n".join(f"P{i % 900}=P{i % 900}+{i}*2+SIN(P{(i + 1) % 900})" for i in range(4000))


async def test_a_large_trio_program_compiles_while_the_loop_serves_others(trio_api):
    r, gaps = await with_ticker(trio_api.put(
        "/controllers/t/programs/BIG", content=TRIO_PROGRAM,
        headers={"content-type": "text/plain"}))
    assert r.status_code == 201, r.text
    assert r.json()["lines"] == 6000
    assert_served_beside(gaps)
    stored = await trio_api.get("/controllers/t/programs/BIG")
    assert stored.text == TRIO_PROGRAM


async def test_a_large_trio_program_with_an_error_stores_nothing(trio_api):
    bad = TRIO_PROGRAM + "\nVR(1)=(3\n"
    r = await trio_api.put("/controllers/t/programs/BAD", content=bad,
                           headers={"content-type": "text/plain"})
    assert r.status_code == 422 and r.json()["code"] == "parse_error"
    assert r.json()["line"] == 6001
    assert (await trio_api.get("/controllers/t/programs/BAD")).status_code == 404


async def test_a_large_plc_compiles_while_the_loop_serves_others(pmac_api):
    r, gaps = await with_ticker(pmac_api.put("/controllers/p/plcs/1", json={"text": PLC_TEXT}))
    assert r.status_code == 200, r.text
    assert r.json()["lines"] >= 4000
    assert_served_beside(gaps)
