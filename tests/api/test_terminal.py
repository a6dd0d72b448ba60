"""POST/GET /controllers/{id}/terminal: dispatch to the kind, with API.md's timing rules."""

from __future__ import annotations

import asyncio
import time

import pytest

pytestmark = pytest.mark.anyio


async def test_virtual_terminal_runs_the_clock_to_the_reply_instant(api):
    r = await api.post("/controllers/d/terminal", json={"command": "ECHO hello"})
    assert r.status_code == 200
    assert r.json() == {"reply": "hello", "error": None, "pending": False}
    assert (await api.get("/controllers/d/clock")).json()["t"] == pytest.approx(0.0005)


async def test_an_immediate_reply_does_not_move_the_clock(api):
    r = await api.post("/controllers/d/terminal", json={"command": "NOW hi"})
    assert r.json() == {"reply": "hi", "error": None, "pending": False}
    assert (await api.get("/controllers/d/clock")).json()["t"] == 0.0


async def test_controller_error_is_still_http_200(api):
    r = await api.post("/controllers/d/terminal", json={"command": "BOGUS"})
    assert r.status_code == 200
    body = r.json()
    assert {k: body[k] for k in ("reply", "error", "pending")} == {
        "reply": "", "error": "ERR003", "pending": False}
    # the wire code stays; the body adds the Turbo SRM meaning (an extension of the contract)
    assert body["error_meaning"] == "unrecognized command or invalid data (syntax error)"
    assert body["not_simulated"] is False


async def test_no_reply_within_1s_simulated_is_pending_then_a_terminal_reply_event(api):
    r = await api.post("/controllers/d/terminal", json={"command": "SLOW"})
    assert r.json() == {"reply": "", "error": None, "pending": True}
    assert (await api.get("/controllers/d/clock")).json()["t"] == pytest.approx(1.0)
    r = await api.post("/controllers/d/clock/run-until",
                       json={"event": {"type": "terminal_reply"}, "timeout_s": 5})
    m = r.json()["matched"]
    assert (m["command"], m["reply"], m["error"], m["t"]) == ("SLOW", "slow", None,
                                                              pytest.approx(2.0))


async def test_a_kind_whose_command_line_never_moves_the_clock_returns_pending_at_once(api):
    await api.post("/controllers", json={"id": "c", "kind": "dummy_cmdline",
                                         "clock": {"mode": "virtual"}})
    r = await api.post("/controllers/c/terminal", json={"command": "ECHO x"})
    assert r.json()["pending"] is True
    assert (await api.get("/controllers/c/clock")).json()["t"] == 0.0


async def test_port_state_persists_between_posts(api):
    await api.post("/controllers/d/terminal", json={"command": "ADDR 3"})
    r = await api.post("/controllers/d/terminal", json={"command": "ADDR ?"})
    assert r.json()["reply"] == "3"


async def test_halted_controller_is_409_watchdog(api):
    r = await api.post("/controllers/d/terminal", json={"command": "HALT"})
    assert r.status_code == 409
    assert r.json()["code"] == "watchdog"


async def test_get_terminal_state_defaults_to_unlocked(api):
    r = await api.get("/controllers/d/terminal")
    assert r.json() == {"locked": False, "pending": []}


@pytest.mark.parametrize("body, field", [({}, "command"), ({"command": 5}, "command"),
                                         ({"command": "x" * 5000}, "command")])
async def test_bad_terminal_body_is_422(api, body, field):
    r = await api.post("/controllers/d/terminal", json=body)
    assert r.status_code == 422
    assert r.json()["field"] == field


async def test_realtime_terminal_awaits_the_reply(api):
    await api.post("/controllers", json={"id": "rt", "kind": "dummy",
                                         "clock": {"mode": "realtime", "factor": 1},
                                         "config": {"reply_delay_s": 0.05}})
    r = await api.post("/controllers/rt/terminal", json={"command": "ECHO later"})
    assert r.json() == {"reply": "later", "error": None, "pending": False}
    ev = (await api.get("/controllers/rt/events", params={"type": "terminal_reply"})).json()
    assert ev["events"][0]["t"] >= 0.05


async def test_realtime_terminal_gives_up_after_1s_simulated_and_the_reply_comes_as_an_event(api):
    """The give-up is decided in simulated time (the command's instant + 1 s): SLOW answers
    2 s after the command, so the POST says pending however late the machine wakes it (a
    loaded machine once saw the reply done when the wait was a wall-clock one)."""
    await api.post("/controllers", json={"id": "rt", "kind": "dummy",
                                         "clock": {"mode": "realtime", "factor": 2}})
    r = await api.post("/controllers/rt/terminal", json={"command": "SLOW"})
    assert r.json() == {"reply": "", "error": None, "pending": True}
    r = await api.post("/controllers/rt/clock/run-until",
                       json={"event": {"type": "terminal_reply", "command": "SLOW"},
                             "timeout_s": 10})
    assert r.json()["matched"]["reply"] == "slow"


async def test_a_realtime_reply_later_than_1s_simulated_is_pending_even_when_the_wait_woke_late(
        api, monkeypatch):
    """A stalled event loop (here: the clock's catch-up runs past both instants before the
    waiting POST is resumed) cannot turn a reply that came 2 s after the command into an
    answered one: it is pending, and announced as a ``terminal_reply`` event (API.md: every
    reply answered pending arrives as that event)."""
    await api.post("/controllers", json={"id": "rt", "kind": "dummy",
                                         "clock": {"mode": "realtime", "factor": 50}})
    real_wait_for = asyncio.wait_for

    async def stalled(awaitable, timeout):  # the loop frozen for 0.2 s wall (10 s simulated)
        time.sleep(0.2)
        return await real_wait_for(awaitable, timeout)

    monkeypatch.setattr(asyncio, "wait_for", stalled)
    r = await api.post("/controllers/rt/terminal", json={"command": "SLOW"})
    assert r.json() == {"reply": "", "error": None, "pending": True}
    ev = (await api.get("/controllers/rt/events", params={"type": "terminal_reply"})).json()
    assert [e["reply"] for e in ev["events"]] == ["slow"]


async def test_paused_realtime_terminal_returns_pending_at_once(api):
    await api.post("/controllers", json={"id": "rt", "kind": "dummy",
                                         "clock": {"mode": "realtime", "paused": True}})
    r = await api.post("/controllers/rt/terminal", json={"command": "ECHO x"})
    assert r.json()["pending"] is True
    t_paused = (await api.get("/controllers/rt/clock")).json()["t"]
    await api.patch("/controllers/rt/clock", json={"paused": False})
    await asyncio.sleep(0.05)
    ev = (await api.get("/controllers/rt/events", params={"type": "terminal_reply"})).json()
    assert [(e["reply"], e["t"]) for e in ev["events"]] == [("x", pytest.approx(t_paused
                                                                                + 0.0005))]


async def test_pmac_control_characters_through_the_rest_terminal(pmac_api):
    """CTRL-P over REST: the positions of motors 1-8 in one line (spec pmac.md §11.9)."""
    r = await pmac_api.post("/controllers/p/terminal", json={"command": "\u0010"})
    assert r.json() == {"reply": "0 0 0 0 0 0 0 0", "error": None, "pending": False}


async def test_pmac_command_posted_on_a_paused_clock_is_pending_and_its_reply_an_event(api):
    """API.md: a reply returned ``pending`` later arrives as a ``terminal_reply`` event — also
    when the POST returned at once because the clock was paused (the background cycle, which
    answers host commands, does not run while paused)."""
    await api.post("/controllers", json={"id": "pm", "kind": "pmac",
                                         "clock": {"mode": "virtual", "paused": True}})
    r = await api.post("/controllers/pm/terminal", json={"command": "PR"})
    assert r.json() == {"reply": "", "error": None, "pending": True}
    await api.patch("/controllers/pm/clock", json={"paused": False})
    r = await api.post("/controllers/pm/clock/run-until",
                       json={"event": {"type": "terminal_reply"}, "timeout_s": 0.1})
    m = r.json()["matched"]
    assert (m["command"], m["reply"], m["error"]) == ("PR", "0", None)
    assert m["t"] < 0.01     # the next background cycle, well before the 1 s terminal wait
    r = await api.post("/controllers/pm/terminal", json={"command": "PR"})
    assert r.json() == {"reply": "0", "error": None, "pending": False}
    ev = (await api.get("/controllers/pm/events", params={"type": "terminal_reply"})).json()
    assert len(ev["events"]) == 1   # an answer the POST returned is not announced again
