"""Issue 22 over the Trio command line as a user drives it: a program with an ON BASICERROR
handler, ON .. GOSUB and PI, stored over REST and RUN from a telnet session (telnetlib3) into a
real ``motionsim serve``; the handler's own PRINT reaches the session, the values read back
there, and the trap is a ``basic_error`` event (spec trio.md §11.3, §11.10)."""

from __future__ import annotations

import asyncio

import httpx

from tests.integration.test_clients_pmac import free_port, motionsim_serve

TIMEOUT_S = 5.0

PROGRAM = """\
ON BASICERROR GOTO trap
ON 2 GOSUB one, two
VR(10) = 100 / (2 * PI)
VR(11) = 1 / VR(12)
STOP
one:
VR(1) = 1 : RETURN
two:
VR(1) = 2 : RETURN
trap:
PRINT "trapped "; RUN_ERROR[0]; " at line "; ERROR_LINE[0]
"""


def test_tj2p5_138_trm_p8_118_program_with_a_handler_run_from_telnet() -> None:
    import telnetlib3

    trio_port = free_port()

    async def session(http: str) -> str:
        reader, writer = await telnetlib3.open_connection(
            "127.0.0.1", trio_port, connect_minwait=0.05, connect_maxwait=0.5)
        seen = []

        async def line(text: str) -> None:
            writer.write(text + "\r\n")
            raw = await asyncio.wait_for(reader.readuntil(b">>"), TIMEOUT_S)
            seen.append(raw if isinstance(raw, str) else raw.decode("latin-1"))

        await line("")
        await line('RUN "DEMO", 2')
        async with httpx.AsyncClient() as client:
            r = await client.post(http + "/clock/advance", json={"seconds": 0.1}, timeout=5)
            assert r.status_code == 200
        for text in ("? VR(1)", "? VR(10)", "? PI", "? RUN_ERROR PROC(2)"):
            await line(text)
        writer.close()
        return "".join(seen).replace("\r", "")

    with motionsim_serve("--trio-port", str(trio_port), "--pmac-port", "0") as svc:
        http = svc.http + "/controllers/trio"
        put = httpx.put(http + "/programs/DEMO", content=PROGRAM,
                        headers={"content-type": "text/plain"}, timeout=5)
        assert put.status_code == 201, put.text
        transcript = asyncio.run(session(http))
        events = httpx.get(http + "/events", params={"type": "basic_error"},
                           timeout=5).json()["events"]
    assert "trapped 1 at line 4" in transcript
    for query, reply in (("? VR(1)", "2.0000"), ("? VR(10)", "15.9155"), ("? PI", "3.1416"),
                         ("? RUN_ERROR PROC(2)", "1.0000")):
        assert f"{query}\n{reply}\n" in transcript, transcript
    assert [(e["process"], e["line"], e["run_error"], e["handler_line"]) for e in events] == [
        (2, 4, 1, 11)]
