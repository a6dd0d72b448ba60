"""Same inputs, same event log: byte-identical JSON through the whole service stack."""

from __future__ import annotations

import json

import pytest
from motionsim.api.main import create_app

from tests.conftest import dummy_settings, rest_client

pytestmark = pytest.mark.anyio


async def _session() -> str:
    async with rest_client(create_app(dummy_settings())) as c:
        for i in range(20):
            await c.post("/controllers/d/terminal", json={"command": f"ECHO {i}"})
            await c.put("/controllers/d/variables/V1", json={"value": i * 0.1})
            await c.post("/controllers/d/clock/advance", json={"seconds": 0.0137})
        await c.post("/controllers/d/terminal", json={"command": "SLOW"})
        await c.post("/controllers/d/clock/run-until",
                     json={"event": {"type": "terminal_reply"}, "timeout_s": 3})
        await c.post("/controllers/d/reset")
        await c.post("/controllers/d/clock/advance", json={"seconds": 0.5})
        events = []
        since = 0
        while True:
            page = (await c.get("/controllers/d/events",
                                params={"since": since, "limit": 50})).json()
            events += page["events"]
            if page["next"] == since:
                break
            since = page["next"]
    return "".join(json.dumps(e, separators=(",", ":")) + "\n" for e in events)


async def test_same_inputs_give_a_byte_identical_log():
    first = await _session()
    second = await _session()
    assert first == second
    lines = first.splitlines()
    assert len(lines) > 150
    types = {json.loads(line)["type"] for line in lines}
    assert types == {"tick", "terminal_reply", "var", "reset"}
