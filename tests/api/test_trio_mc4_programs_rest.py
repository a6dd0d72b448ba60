"""Issue 22 through the public surfaces, as a user would: the homing routine stored and run
over REST with the datum switch driven by ``PUT .../variables/IN(5)``; the start-up
program's parameters read back at the Trio command line over TCP."""

from __future__ import annotations

import asyncio
from pathlib import Path

import pytest
from motionsim.api.main import create_app
from motionsim.api.trio_terminal.server import serve_trio
from motionsim.app.registry import Registry

from tests.api.conftest import FAST
from tests.api.wire_helpers import connect
from tests.conftest import dummy_settings, rest_client

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "trio"
BASE = "/controllers/m4"


@pytest.mark.anyio
async def test_homing_routine_over_rest_with_the_datum_switch_from_in_writes():
    settings = dummy_settings(controllers=[{
        "id": "m4", "kind": "trio", "clock": {"mode": "virtual"},
        "config": {**FAST, "model": "mc4xx"}}])
    async with rest_client(create_app(settings)) as api:

        async def advance(seconds: float) -> None:
            r = await api.post(f"{BASE}/clock/advance", json={"seconds": seconds})
            assert r.status_code == 200

        async def switch(value: int) -> None:
            r = await api.put(f"{BASE}/variables/IN(5)", json={"value": value})
            assert r.status_code == 200

        await switch(1)  # clear (active low)
        r = await api.put(f"{BASE}/programs/homing", content=(EXAMPLES / "mc4_homing.bas")
                          .read_text(), headers={"content-type": "text/plain"})
        assert r.status_code == 201
        assert (await api.post(f"{BASE}/programs/homing/run", json={"process": 3})
                ).status_code in (200, 201)
        await advance(0.5005)
        axis = (await api.get(f"{BASE}/axes/0")).json()
        assert axis["mtype"] == 12 and axis["dpos"] < 0
        await switch(0)
        await advance(0.5)
        await switch(1)
        await advance(4.0)
        datums = (await api.get(f"{BASE}/events", params={"type": "datum"})).json()["events"]
        assert sorted(e["axis"] for e in datums) == [0, 1]
        a0, a1 = [(await api.get(f"{BASE}/axes/{n}")).json() for n in (0, 1)]
        assert (a0["dpos"], a1["dpos"], a0["mtype"], a1["mtype"]) == (0.0, 0.0, 0, 0)
        assert (await api.get(f"{BASE}/variables/VR(10)")).json()["value"] == 1.0
        r = await api.post(f"{BASE}/terminal", json={"command": "? DATUM_IN AXIS(0)"})
        assert r.json()["reply"] == "5.0000"


def test_start_up_program_parameters_read_back_at_the_trio_port() -> None:
    text = (EXAMPLES / "mc4_startup.bas").read_text()

    async def scenario(handle, port):
        reader, writer = await connect(port)
        writer.write(b"\r\n")
        await asyncio.wait_for(reader.readuntil(b">>"), 2.0)
        ctrl = handle.controller
        handle.apply(ctrl.store_program, "STARTUP", text)
        handle.apply(ctrl.run_program, "STARTUP", 1)
        handle.clock.advance(0.5)
        replies = []
        for cmd in (b"? P_GAIN AXIS(1)", b"PRINT FE AXIS(0)", b"? LIMIT_BUFFERED",
                    b"? VFF_GAIN AXIS(2)"):
            writer.write(cmd + b"\r\n")
            replies.append(await asyncio.wait_for(reader.readuntil(b">>"), 2.0))
        writer.close()
        return replies

    async def main():
        registry = Registry()
        handle = registry.add("trio", "t", clock="virtual", config={"model": "mc4xx"})
        server = await serve_trio(handle, "127.0.0.1", 0)
        try:
            return await scenario(handle, server.sockets[0].getsockname()[1])
        finally:
            server.close()
            await server.wait_closed()
            await registry.close()

    replies = asyncio.run(main())
    assert [r.split(b"\r\n")[1] for r in replies] == [b"0.8000", b"0.0000", b"16.0000",
                                                        b"12.0000"]
