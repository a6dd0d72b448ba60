"""One binding per GLOBAL / CONSTANT name (issue 33 item 7; sim/trio/scope.py ``rebinding``).

Duplicate ``GLOBAL`` names across programs and a ``CONSTANT`` that rebinds a GLOBAL were
accepted silently, redirecting another program's name. The MC4 help gives no rule ``[BK]``;
the simulator refuses a second, different binding — at compile time when the first is known
(a 422 naming both), at run time (a BASIC error) when two stored programs meet only then — and
accepts the same declaration again (a start-up program run twice).
"""

from __future__ import annotations

import pytest
from motionsim.api.main import create_app

from tests.conftest import dummy_settings, rest_client

pytestmark = pytest.mark.anyio
T = "/controllers/t"
PLAIN = {"content-type": "text/plain"}


@pytest.fixture
async def api():
    settings = dummy_settings(controllers=[
        {"id": "t", "kind": "trio", "clock": {"mode": "virtual"}, "config": {"model": "mc4xx"}}])
    async with rest_client(create_app(settings)) as client:
        yield client


async def _run(api, name: str, text: str, process: int = 1) -> dict:
    assert (await api.put(f"{T}/programs/{name}", content=text, headers=PLAIN)).status_code == 201
    await api.post(f"{T}/programs/{name}/run", json={"process": process})
    await api.post(f"{T}/clock/advance", json={"seconds": 0.1})
    return {p["program"]: p for p in (await api.get(f"{T}/processes")).json()}[name]


async def test_the_same_declaration_twice_is_fine(api) -> None:
    text = 'GLOBAL "feed", 10\nCONSTANT "top", 5\nfeed = top'
    assert (await _run(api, "A", text))["error"] is None
    assert (await _run(api, "B", text, 2))["error"] is None
    assert (await api.get(f"{T}/variables/VR(10)")).json()["value"] == 5.0


@pytest.mark.parametrize("second", ['GLOBAL "feed", 11', 'CONSTANT "feed", 3'])
async def test_a_different_binding_is_refused_when_compiled_after_the_first_ran(
        api, second) -> None:
    assert (await _run(api, "A", 'GLOBAL "feed", 10'))["error"] is None
    r = await api.put(f"{T}/programs/B", content=second, headers=PLAIN)
    assert r.status_code == 422
    assert "already GLOBAL VR(10)" in r.json()["message"]


async def test_two_stored_programs_meet_at_run_time(api) -> None:
    for name, text in (("A", 'GLOBAL "feed", 10'), ("B", 'GLOBAL "feed", 12\nfeed = 1')):
        assert (await api.put(f"{T}/programs/{name}", content=text, headers=PLAIN)
                ).status_code == 201
    assert (await _run(api, "A", 'GLOBAL "feed", 10'))["error"] is None
    r = await api.post(f"{T}/programs/B/run", json={"process": 2})  # compiled again at RUN
    assert r.status_code == 422 and "already GLOBAL VR(10)" in r.json()["message"]
    await api.post(f"{T}/clock/advance", json={"seconds": 0.1})
    assert (await api.get(f"{T}/variables/VR(12)")).json()["value"] == 0.0


async def test_at_run_time_when_both_were_compiled_before(api) -> None:
    """Program B waits, A declares, then B declares otherwise: a BASIC error of B."""
    text_b = 'WAIT UNTIL VR(1) = 1\nGLOBAL "feed", 12\nVR(2) = 5'
    assert (await api.put(f"{T}/programs/B", content=text_b, headers=PLAIN)).status_code == 201
    await api.post(f"{T}/programs/B/run", json={"process": 2})
    assert (await _run(api, "A", 'GLOBAL "feed", 10\nVR(1) = 1'))["error"] is None
    await api.post(f"{T}/clock/advance", json={"seconds": 0.1})
    procs = {p["program"]: p for p in (await api.get(f"{T}/processes")).json()}
    assert "already GLOBAL VR(10)" in procs["B"]["error"]
    assert (await api.get(f"{T}/variables/VR(2)")).json()["value"] == 0.0


async def test_within_one_program_too(api) -> None:
    r = await api.put(f"{T}/programs/C", content='GLOBAL "g", 1\nCONSTANT "g", 2', headers=PLAIN)
    assert r.status_code == 422 and r.json()["line"] == 2
