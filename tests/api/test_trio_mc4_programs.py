"""Issue 22 through REST, as a user drives it: the MC4 programs of
``tests/sim/trio/test_mc4_programs.py`` stored with PUT on an ``mc4xx`` controller, run, and
read back (axes, terminal, events); bad MC4 input is a 422 naming program, line and column."""

from __future__ import annotations

from collections.abc import AsyncIterator

import httpx
import pytest
from motionsim.api.main import create_app

from tests.conftest import dummy_settings, rest_client
from tests.sim.trio.test_mc4_programs import CAMRUN, INITIALISE, STARTUP

pytestmark = pytest.mark.anyio

BASE = "/controllers/m4"
TEXT = {"content-type": "text/plain"}


@pytest.fixture
async def mc4_api() -> AsyncIterator[httpx.AsyncClient]:
    settings = dummy_settings(controllers=[{
        "id": "m4", "kind": "trio", "clock": {"mode": "virtual"},
        "config": {"model": "mc4xx", "speed": 1000.0, "accel": 100000.0, "decel": 100000.0},
    }])
    async with rest_client(create_app(settings)) as client:
        yield client


async def test_issue22_mc4_start_up_and_cam_programs_over_rest(mc4_api):
    for name, text in (("INITIALISE", INITIALISE), ("STARTUP", STARTUP), ("CAMRUN", CAMRUN)):
        r = await mc4_api.put(f"{BASE}/programs/{name}", content=text, headers=TEXT)
        assert r.status_code == 201, r.text
    r = await mc4_api.post(f"{BASE}/programs/STARTUP/run", json={"process": 1})
    assert r.status_code < 300, r.text
    await mc4_api.post(f"{BASE}/clock/advance", json={"seconds": 3.0})
    assert (await mc4_api.get(f"{BASE}/axes/0")).json()["dpos"] == pytest.approx(50.0)
    assert (await mc4_api.get(f"{BASE}/axes/1")).json()["dpos"] == pytest.approx(100.0)
    r = (await mc4_api.post(f"{BASE}/terminal", json={"command": "? machine_state"})).json()
    assert r["reply"] == "2.0000" and r["output"] == ["cam ready: CYCLOID36"]
    r = (await mc4_api.post(f"{BASE}/terminal", json={"command": "? PI * 2"})).json()
    assert r["reply"] == "6.2832"
    events = (await mc4_api.get(f"{BASE}/events", params={"type": "basic_error"})).json()
    assert events["events"] == []
    procs = (await mc4_api.get(f"{BASE}/processes")).json()
    assert procs  # both ran
    mtypes = (await mc4_api.get(f"{BASE}/events", params={"type": "move_start"})).json()
    assert sorted((e["axis"], e["mtype"]) for e in mtypes["events"]) == [(0, 20), (1, 1)]


@pytest.mark.parametrize(("text", "line", "column", "program"), [
    ("DIM n AS INTEGER\nDIM n AS FLOAT\n", 2, 1, "BAD"),
    ('INCLUDE "MISSING"\n', 1, 1, "BAD"),
    ("ON BASICERROR GOTO\n", 1, 19, "BAD"),
    ("PI = 3\n", 1, 1, "BAD"),
])
async def test_issue22_bad_mc4_input_over_rest_is_422_with_program_line_column(
        mc4_api, text, line, column, program):
    r = await mc4_api.put(f"{BASE}/programs/bad", content=text, headers=TEXT)
    assert r.status_code == 422
    body = r.json()
    assert (body["code"], body["program"], body["line"], body["column"]) == (
        "parse_error", program, line, column)
    assert (await mc4_api.get(f"{BASE}/programs/bad")).status_code == 404


async def test_issue22_move_of_an_infinite_distance_at_the_rest_terminal_is_an_error(mc4_api):
    r = (await mc4_api.post(f"{BASE}/terminal", json={"command": "MOVE(1e999)"})).json()
    assert r["error"] is not None and "out of range" in r["error"]
    await mc4_api.post(f"{BASE}/clock/advance", json={"seconds": 0.1})
    assert (await mc4_api.get(f"{BASE}/axes/0")).json()["mtype"] in (0, None)
