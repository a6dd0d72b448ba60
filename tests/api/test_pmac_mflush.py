"""``MFLUSH`` through the REST terminal and the PMAC Ethernet port (TUM p250): a write left
queued behind the last move of a rotary program is removed and never fires; a write streamed
after it does, on the RTI grid."""

from __future__ import annotations

import pytest

from tests.api.pmac_ethernet.test_pmac_server import Client, run

BASE = "/controllers/p"
SETUP = ("&1 DEFINE ROT 200", "&1 B0", "OPEN ROT", "X10 TM100 TA10 TS0", "M1==1", "CLOSE", "R")


async def _say(api, command: str) -> dict:
    r = await api.post(f"{BASE}/terminal", json={"command": command})
    assert r.status_code == 200
    return r.json()


async def _advance(api, seconds: float) -> None:
    r = await api.post(f"{BASE}/clock/advance", json={"seconds": seconds})
    assert r.status_code == 200


async def _mvars(api) -> list[dict]:
    return (await api.get(f"{BASE}/events", params={"type": "mvar"})).json()["events"]


@pytest.mark.anyio
@pytest.mark.parametrize("flush", [True, False])
async def test_rest_terminal_mflush_removes_the_stale_write_the_next_one_fires(pmac_api, flush):
    for command in SETUP:
        assert (await _say(pmac_api, command))["error"] is None
    await _advance(pmac_api, 0.3)  # ran out of lines: M1 queued behind the last move
    if flush:
        body = await _say(pmac_api, "&1 MFLUSH")
        assert (body["reply"], body["error"]) == ("", None)
    for command in ("OPEN ROT", "X20", "M2==1", "X30", "CLOSE"):
        assert (await _say(pmac_api, command))["error"] is None
    await _advance(pmac_api, 0.5)
    names = [e["name"] for e in await _mvars(pmac_api)]
    assert names == (["M2"] if flush else ["M1", "M2"])


def test_mflush_over_the_ethernet_port_is_acknowledged_and_empties_the_queue() -> None:
    """The TCP port: with I3 = 2 MFLUSH answers the bare ACK; the stale M1 never fires."""

    async def scenario(handle, port):
        c = await Client.connect(port)
        await c.ask("i3=2")
        for command in SETUP:
            assert await c.ask(command) == b"\x06", command
        handle.clock.advance(0.3)
        ack = await c.ask("MFLUSH")
        for command in ("OPEN ROT", "X20", "M2==1", "X30", "CLOSE"):
            await c.ask(command)
        handle.clock.advance(0.5)
        await c.close()
        return ack, [e["name"] for e in handle.controller.log.events("mvar")]

    ack, names = run(scenario, kind="pmac")
    assert ack == b"\x06"
    assert names == ["M2"]
