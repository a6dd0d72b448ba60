"""Program memory is bounded like a card's (issue 33 item 3; sim/trio/data_memory.py).

``DIM a(100000000) AS INTEGER`` was accepted and its RUN allocated 800 MB on the event loop;
``DIM s AS STRING(2000000000)`` with ``s = s + s`` reached MemoryError. Now a DIM that can
never fit, or a longer string, is refused when stored (422 naming the limit, nothing stored);
the running processes of one controller share its data memory (a DIM that does not fit beside
the others stops its program with a BASIC error naming the free bytes), and a stopped process
gives its data back. Another controller's memory is its own.
"""

from __future__ import annotations

import httpx
import pytest
from motionsim.api.main import create_app
from motionsim.sim.trio.card.data_memory import DATA_BYTES, MAX_STRING, NUMBER_BYTES

from tests.conftest import dummy_settings, rest_client

pytestmark = pytest.mark.anyio

PLAIN = {"content-type": "text/plain"}
LIMIT = DATA_BYTES // NUMBER_BYTES  # numbers one controller's data memory holds


@pytest.fixture
async def api():
    settings = dummy_settings(controllers=[
        {"id": "t", "kind": "trio", "clock": {"mode": "virtual"}, "config": {"model": "mc4xx"}},
        {"id": "u", "kind": "trio", "clock": {"mode": "virtual"}, "config": {"model": "mc4xx"}},
    ])
    async with rest_client(create_app(settings)) as client:
        yield client


async def put(api: httpx.AsyncClient, name: str, text: str, c: str = "t") -> httpx.Response:
    return await api.put(f"/controllers/{c}/programs/{name}", content=text, headers=PLAIN)


async def test_the_limits() -> None:
    assert (DATA_BYTES, MAX_STRING, NUMBER_BYTES) == (1 << 20, 65_535, 8)


@pytest.mark.parametrize("text", ["DIM a(100000000) AS INTEGER", "DIM a(400000000) AS FLOAT",
                                  f"DIM a({LIMIT + 1}) AS BOOLEAN",
                                  "DIM s AS STRING(2000000000)",
                                  f"DIM s AS STRING({MAX_STRING + 1})",
                                  "DIM s(100) AS STRING(20000)"])
async def test_a_dim_that_can_never_fit_is_refused_when_stored(api, text) -> None:
    r = await put(api, "BIG", text)
    assert r.status_code == 422
    body = r.json()
    assert body["line"] == 1
    assert str(DATA_BYTES) in body["message"] or str(MAX_STRING) in body["message"]
    assert (await api.get("/controllers/t/programs/BIG")).status_code == 404


async def test_the_limit_itself_is_accepted_and_runs(api) -> None:
    text = f"DIM a({LIMIT}) AS INTEGER\na({LIMIT - 1})=7\nVR(1)=a({LIMIT - 1})"
    assert (await put(api, "FULL", text)).status_code == 201
    await api.post("/controllers/t/programs/FULL/run", json={"process": 1})
    await api.post("/controllers/t/clock/advance", json={"seconds": 0.5})
    assert (await api.get("/controllers/t/variables/VR(1)")).json()["value"] == 7.0


async def test_a_string_doubling_stops_at_its_declared_length(api) -> None:
    text = (f'DIM s AS STRING({MAX_STRING})\ns = "ab"\nn = 0\nWHILE n < 40\ns = s + s\n'
            "n = n + 1\nWEND\nVR(2) = LEN(s)")
    assert (await put(api, "GROW", text)).status_code == 201
    await api.post("/controllers/t/programs/GROW/run", json={"process": 1})
    await api.post("/controllers/t/clock/advance", json={"seconds": 2})
    assert (await api.get("/controllers/t/variables/VR(2)")).json()["value"] == MAX_STRING
    (proc,) = (await api.get("/controllers/t/processes")).json()
    assert proc["state"] == "stopped" and proc["error"] is None


async def test_processes_of_one_controller_share_its_memory_not_anothers(api) -> None:
    big = LIMIT * 3 // 4
    await put(api, "HOLD", f"DIM a({big}) AS INTEGER\nWHILE 1\nWEND")
    await put(api, "MORE", f"DIM b({big}) AS INTEGER\nVR(3)=1")
    await put(api, "MORE", f"DIM b({big}) AS INTEGER\nVR(3)=1", c="u")
    await api.post("/controllers/t/programs/HOLD/run", json={"process": 1})
    await api.post("/controllers/t/clock/advance", json={"seconds": 0.1})
    await api.post("/controllers/t/programs/MORE/run", json={"process": 2})
    await api.post("/controllers/u/programs/MORE/run", json={"process": 2})
    for c in ("t", "u"):
        await api.post(f"/controllers/{c}/clock/advance", json={"seconds": 0.2})
    procs = {p["process"]: p for p in (await api.get("/controllers/t/processes")).json()}
    assert procs[1]["state"] == "running"
    assert procs[2]["state"] == "stopped"
    free = DATA_BYTES - big * NUMBER_BYTES
    assert f"needs {big * NUMBER_BYTES} bytes, {free} of {DATA_BYTES}" in procs[2]["error"]
    assert (await api.get("/controllers/t/variables/VR(3)")).json()["value"] == 0.0
    # the other controller's memory is its own
    assert (await api.get("/controllers/u/variables/VR(3)")).json()["value"] == 1.0
    # a stopped process gives its data back
    await api.post("/controllers/t/terminal", json={"command": "STOP \"HOLD\""})
    await api.post("/controllers/t/clock/advance", json={"seconds": 0.1})
    await api.post("/controllers/t/programs/MORE/run", json={"process": 2})
    await api.post("/controllers/t/clock/advance", json={"seconds": 0.2})
    assert (await api.get("/controllers/t/variables/VR(3)")).json()["value"] == 1.0
