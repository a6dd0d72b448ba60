"""``PC`` over the PMAC Ethernet protocol (VR_PMAC_GETRESPONSE), on the real ``pmac`` kind."""

from __future__ import annotations

from tests.api.pmac_ethernet.test_pmac_server import Client, run


def test_pc_in_a_getresponse_answers_program_and_offset() -> None:
    async def scenario(handle, port):
        c = await Client.connect(port)
        got = [await c.ask("i3=2")]
        for line in ("OPEN PROG 5 CLEAR", "TM100", "X10", "CLOSE", "&1B5"):
            got.append(await c.ask(line))
        got.append(await c.ask("&1PC"))
        got.append(await c.ask("&1PE"))
        await c.close()
        return got

    got = run(scenario, kind="pmac")
    assert got[-2:] == [b"P5:0\r\x06", b"P5:0\r\x06"]
    assert all(g == b"\x06" for g in got[:-2])
