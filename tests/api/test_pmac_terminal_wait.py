"""API.md "The terminal": a PMAC reply that comes within the 1 s of simulated time a virtual
POST waits is returned by the POST and not announced again as a ``terminal_reply`` event —
also when it comes exactly at the end of that second; one later is ``pending``, then the event.
Here a background cycle is 1000 servo cycles of 1 ms: a command is answered 1 s after it is
sent."""

from __future__ import annotations

import pytest

pytestmark = pytest.mark.anyio

SLOW = {"servo_hz": 1000, "background_cycles": 1000}


async def _replies(api) -> list[dict]:
    page = (await api.get("/controllers/pm/events", params={"type": "terminal_reply"})).json()
    return page["events"]


@pytest.mark.parametrize(("start", "cycles", "reply_t"), [
    (0.0, 1000, 1.0), (1.3, 1000, 2.3),
    (0.499999999, 1001, 1.5),  # 1 s + 1 ns later: within the clock's float tolerance
])
async def test_a_reply_at_the_end_of_the_second_is_returned_and_not_announced(
    api, start, cycles, reply_t
):
    await api.post("/controllers", json={"id": "pm", "kind": "pmac",
                                         "config": {**SLOW, "background_cycles": cycles},
                                         "clock": {"mode": "virtual"}})
    if start:
        await api.post("/controllers/pm/clock/advance", json={"seconds": start})
    r = await api.post("/controllers/pm/terminal", json={"command": "I16"})
    assert r.json() == {"reply": "5", "error": None, "pending": False}
    clock = (await api.get("/controllers/pm/clock")).json()
    assert clock["t"] == pytest.approx(reply_t)
    assert await _replies(api) == []


async def test_a_reply_later_than_one_second_is_pending_then_an_event(api):
    await api.post("/controllers", json={"id": "pm", "kind": "pmac",
                                         "config": {**SLOW, "background_cycles": 1001},
                                         "clock": {"mode": "virtual"}})
    r = await api.post("/controllers/pm/terminal", json={"command": "I16"})
    assert r.json() == {"reply": "", "error": None, "pending": True}
    await api.post("/controllers/pm/clock/advance", json={"seconds": 0.01})
    (ev,) = await _replies(api)
    assert (ev["command"], ev["reply"], ev["error"]) == ("I16", "5", None)
    assert ev["t"] == pytest.approx(1.001)
