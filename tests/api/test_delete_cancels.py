"""Deleting a controller ends every call still waiting on it (issue 23, items 2 and 5).

An ``advance``, a ``run-until`` or a terminal command waiting for its reply answers 410
``controller_deleted`` as soon as ``DELETE /controllers/{id}`` is served, and the deleted
controller's simulation stops there (its simulated time no longer moves). A virtual
``run-until`` stopped by the wall-time budget says ``wall_timeout``, not ``timeout``.
"""

from __future__ import annotations

import asyncio
import time

import httpx
import pytest
from motionsim.api.main import create_app
from motionsim.app import registry as registry_module
from motionsim.app.settings import Settings

from tests.api.test_clock_slices import _busy
from tests.conftest import rest_client

pytestmark = pytest.mark.anyio


def _settings(clock: dict | None = None) -> Settings:
    return Settings(controllers=[
        {"id": "p", "kind": "pmac", "clock": clock or {"mode": "virtual"}},
        {"id": "q", "kind": "pmac", "clock": {"mode": "virtual"}}], pmac_port=0, trio_port=0)


async def _deleted_while_waiting(api: httpx.AsyncClient, call) -> tuple[httpx.Response, float]:
    """Start ``call``, delete ``p`` once it is under way; its response and the wall seconds
    between the DELETE's answer and the call's."""
    env = api.app.state.registry.get("p").controller.env
    waiting = asyncio.ensure_future(call)
    await asyncio.sleep(0.1)
    assert not waiting.done()
    assert (await api.delete("/controllers/p")).status_code == 204
    deleted_at = time.monotonic()
    response = await asyncio.wait_for(waiting, timeout=10)
    late = time.monotonic() - deleted_at
    t_then = env.now
    await asyncio.sleep(0.2)
    assert env.now == t_then          # nothing simulates the deleted controller any more
    return response, late


def _is_410(response: httpx.Response) -> None:
    assert response.status_code == 410, response.text
    body = response.json()
    assert body["code"] == "controller_deleted" and body["controller"] == "p"
    assert "deleted" in body["message"]


async def test_delete_ends_an_advance_of_a_busy_controller_with_410():
    async with rest_client(create_app(_settings())) as api:
        await _busy(api)
        response, _ = await _deleted_while_waiting(
            api, api.post("/controllers/p/clock/advance", json={"seconds": 1000.0}))
        _is_410(response)
        assert (await api.get("/controllers/p")).status_code == 404
        other = await api.post("/controllers/q/clock/advance", json={"seconds": 0.01})
        assert other.status_code == 200


async def test_delete_ends_a_run_until_with_410():
    async with rest_client(create_app(_settings())) as api:
        await _busy(api)
        response, _ = await _deleted_while_waiting(api, api.post(
            "/controllers/p/clock/run-until",
            json={"event": {"type": "watchdog"}, "timeout_s": 100000.0}))
        _is_410(response)


async def test_delete_ends_a_terminal_command_waiting_for_its_reply_with_410():
    """A realtime clock at factor 0.001: the PMAC answers in a background cycle some wall
    seconds away, so the terminal call is still waiting when the controller is deleted."""
    async with rest_client(create_app(_settings({"mode": "realtime", "factor": 0.001}))) as api:
        response, _ = await _deleted_while_waiting(
            api, api.post("/controllers/p/terminal", json={"command": "I10"}))
        _is_410(response)


async def test_a_call_started_after_the_delete_is_404_and_a_new_p_is_untouched():
    async with rest_client(create_app(_settings())) as api:
        await _busy(api)
        await _deleted_while_waiting(
            api, api.post("/controllers/p/clock/advance", json={"seconds": 1000.0}))
        created = await api.post("/controllers", json={"id": "p", "kind": "pmac",
                                                       "clock": {"mode": "virtual"}})
        assert created.status_code == 201
        assert created.json()["clock"]["t"] == 0
        r = await api.post("/controllers/p/clock/advance", json={"seconds": 0.5})
        assert r.status_code == 200 and r.json()["t"] == pytest.approx(0.5)


async def test_a_virtual_run_until_stopped_by_the_wall_budget_says_wall_timeout(monkeypatch):
    """API.md: ``timeout`` is ``timeout_s`` of simulated time; the wall budget is
    ``wall_timeout`` (the clock stays where it got to, short of ``timeout_s``)."""
    monkeypatch.setattr(registry_module, "RUN_UNTIL_WALL_CAP_S", 0.3)
    async with rest_client(create_app(_settings())) as api:
        await _busy(api)
        body = (await api.post("/controllers/p/clock/run-until", json={
            "event": {"type": "watchdog"}, "timeout_s": 100000.0})).json()
        assert (body["matched"], body["outcome"]) == (None, "wall_timeout")
        assert 0 < body["clock"]["t"] < 100000.0
        short = (await api.post("/controllers/p/clock/run-until", json={
            "event": {"type": "watchdog"}, "timeout_s": 0.01})).json()
        assert short["outcome"] == "timeout"
