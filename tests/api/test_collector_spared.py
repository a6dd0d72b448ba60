"""Large compiled forms are not left to the cyclic garbage collector (issue 23, item 1).

A batch of 1 000 long rotary lines, a 14 000-line Trio program or a 4 000-line PLC compiles
to hundreds of thousands of objects. Left in the collector's young generation, they would be
walked in one go by its next pass — on the event loop, or in the worker thread holding the
interpreter lock — for tens of milliseconds, and again by each older pass (a 1000-line batch
cost ``/health`` 130 ms in ``bench/bench_attacks.py``). They are frozen once compiled: the
collector's generations grow by a small fraction of them, and what the program does is
unchanged (the rotary lines are stored, the program reads back, the PLC lists its lines).
"""

from __future__ import annotations

import gc

import pytest

pytestmark = pytest.mark.anyio

LONG = "X{i} " + " ".join(f"P{j}=P{j}+{{i}}" for j in range(20))
TRIO_PROGRAM = "\n".join(f"VR({i % 500})=VR({i % 500})+{i}*2" for i in range(14000))
PLC_TEXT = "\n".join(f"P{i % 900}=P{i % 900}+{i}*2+SIN(P{(i + 1) % 900})" for i in range(4000))

#: Tracked objects a request may leave to the collector (its own few thousand; the compiled
#: forms below are 150 000 to 500 000).
SPARED = 40_000


def collected() -> int:
    """Objects in the collector's three generations (frozen ones are in none)."""
    return sum(len(gc.get_objects(generation)) for generation in range(3))


async def test_a_batch_of_long_rotary_lines_is_stored_outside_the_collector(pmac_api):
    lines = [LONG.format(i=i) for i in range(1000)]
    body = {"lines": lines}
    assert (await pmac_api.put("/controllers/p/coord/1/rotary",
                               json={"size_words": 65_536})).status_code == 200
    before = collected()
    r = await pmac_api.post("/controllers/p/coord/1/rotary/lines", json=body)
    grown = collected() - before
    assert r.status_code == 200 and r.json()["stored"] == 1000, r.text
    assert grown < SPARED, grown


async def test_a_large_trio_program_is_stored_outside_the_collector(trio_api):
    before = collected()
    r = await trio_api.put("/controllers/t/programs/BIG", content=TRIO_PROGRAM,
                           headers={"content-type": "text/plain"})
    grown = collected() - before
    assert r.status_code == 201 and r.json()["lines"] == 14000, r.text
    assert grown < SPARED, grown
    assert (await trio_api.get("/controllers/t/programs/BIG")).text == TRIO_PROGRAM


async def test_a_large_plc_is_stored_outside_the_collector(pmac_api):
    before = collected()
    r = await pmac_api.put("/controllers/p/plcs/2", json={"text": PLC_TEXT})
    grown = collected() - before
    assert r.status_code == 200 and r.json()["lines"] >= 4000, r.text
    assert grown < SPARED, grown
