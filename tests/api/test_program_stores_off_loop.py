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


async def test_list_plc_of_a_large_stored_plc_is_listed_at_the_store_not_per_list(
        pmac_api, monkeypatch):
    """``LIST PLC n`` (spec pmac.md §11.8: the card lists a PLC decompiled): the listing of a PLC
    stored by ``PUT`` is worked out with its compile, beside the loop; each ``LIST`` — a host
    reads a program in windows, ``LIST PLC n,start,len`` — answers from it, rather than
    decompiling 4 000 lines (0.1 s) on the loop again."""
    import threading

    from motionsim.sim.pmac.host import listing

    assert (await pmac_api.put("/controllers/p/plcs/1", json={"text": PLC_TEXT})).is_success
    loop_thread = threading.get_ident()
    decompiled: list[str] = []
    canonical = listing.canonical

    def spied(source: str) -> str:
        if threading.get_ident() == loop_thread:
            decompiled.append(source)
        return canonical(source)

    monkeypatch.setattr(listing, "canonical", spied)
    whole = await pmac_api.post("/controllers/p/terminal", json={"command": "LIST PLC 1"})
    part = await pmac_api.post("/controllers/p/terminal", json={"command": "LIST PLC 1,100,20"})
    assert not decompiled, len(decompiled)
    monkeypatch.undo()
    expected = [text for _, text in listing.entries(PLC_TEXT.splitlines())]
    assert whole.json()["reply"].split("\r") == expected
    assert expected[-1] == "RET"
    window = [f"{off}:{text}" for off, text in listing.entries(PLC_TEXT.splitlines())
              if 100 <= off < 120]
    assert part.json()["reply"].split("\r") == window
