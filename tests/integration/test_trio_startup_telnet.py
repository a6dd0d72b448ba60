"""A Trio start-up sequence typed over telnet (telnetlib3) into a real ``motionsim serve``: the
system / axis parameters and digital I/O answer as on the controller's command line, the
output change is in the event log, an input set over REST reads back (spec trio.md §9.9,
§10.11; docs/API.md Trio variables ``IN(n)`` / ``OP(n)``)."""

from __future__ import annotations

import asyncio

import httpx

from tests.integration.test_clients_pmac import free_port, motionsim_serve

TIMEOUT_S = 5.0


def test_startup_lines_over_telnet_answer_and_log_the_output_change() -> None:
    import telnetlib3

    trio_port = free_port()
    lines = ["WDOG=ON", "?WDOG", "FS_LIMIT=5000", "?FS_LIMIT", "?ERRORMASK", "?AXISSTATUS",
             "?MOTION_ERROR", "OP(8,ON)", "?READ_OP(8)", "?IN(3)"]

    async def session() -> list[str]:
        reader, writer = await telnetlib3.open_connection(
            "127.0.0.1", trio_port, connect_minwait=0.05, connect_maxwait=0.5)
        got = []
        for line in ["", *lines]:
            writer.write(line + "\r\n")
            raw = await asyncio.wait_for(reader.readuntil(b">>"), TIMEOUT_S)
            got.append((raw if isinstance(raw, str) else raw.decode("latin-1")).replace("\r", ""))
        writer.close()
        return got[1:]

    with motionsim_serve("--trio-port", str(trio_port), "--pmac-port", "0") as svc:
        assert svc.listening.get("telnet") == trio_port, svc.lines
        http = svc.http + "/controllers/trio"
        put = httpx.put(http + "/variables/IN(3)", json={"value": 1}, timeout=5)
        assert put.status_code == 200 and put.json() == {"name": "IN(3)", "value": 1.0}
        got = asyncio.run(session())
        events = httpx.get(http + "/events", params={"type": ["output", "wdog"]},
                           timeout=5).json()["events"]
    replies = [g.rsplit(line + "\n", 1)[-1].removesuffix(">>").strip("\n")
               for g, line in zip(got, lines, strict=True)]
    assert replies == ["", "1.0000", "", "5000.0000", "268.0000", "0.0000", "0.0000", "",
                       "1.0000", "1.0000"]
    assert [(e["type"], {k: v for k, v in e.items() if k in ("on", "output", "value")})
            for e in events] == [("wdog", {"on": True}), ("output", {"output": 8, "value": 1})]
