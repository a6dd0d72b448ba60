"""``SEND`` lines of PLC programs on the PMAC Ethernet port (TSRM p470, p37, p67; PSRM p347;
spec §2.1, §5.1), over real loopback sockets on a virtual clock.

The line goes to the active response port (the connection whose command ran last): READREADY
then says output is waiting and GETBUFFER returns it, framed as a program-originated line
(no ACK). With I64=0 the next GETRESPONSE returns it ahead of the command's reply, up to that
reply's ACK; with I64=1 it starts with ``<STX>`` and GETRESPONSE returns it alone (up to its
CR), the reply staying queued for GETBUFFER.
"""

from __future__ import annotations

from motionsim.api.pmac_ethernet.server import serve_pmac

from tests.api.pmac_ethernet.test_pmac_server import Client
from tests.api.wire_helpers import run_served

READREADY = bytes.fromhex("c0c2000000000002")
GETBUFFER = bytes.fromhex("c0c5000000000800")

PLC = ["I5=2", "OPEN PLC 1 CLEAR", 'SEND"HOMED 3"', "DIS PLC 1", "CLOSE"]


def run(scenario):
    return run_served(serve_pmac, "pmac", "pmac", scenario)


async def _load(c: Client, i64: int) -> None:
    assert await c.ask(f"I3=2 I6=1 I64={i64}") == b"\x06"
    for line in PLC:
        assert await c.ask(line) == b"\x06"


def test_tsrm_p470_send_waits_on_the_active_port_for_readready_and_getbuffer() -> None:
    async def scenario(handle, port):
        other = await Client.connect(port)
        c = await Client.connect(port)
        await _load(c, 0)
        assert await other.ask("P2") == b"0\r\x06"
        await c.ask("ENA PLC 1")  # c is now the active response port; PLC 1 scans and sends
        ready = await c.send(READREADY, 2)
        text = await c.send(GETBUFFER)
        empty = await c.send(READREADY, 2)
        other_ready = await other.send(READREADY, 2)
        await c.close()
        await other.close()
        sends = [(e["plc"], e["text"]) for e in handle.controller.log.events("plc_send")]
        return ready, text, empty, other_ready, sends

    ready, text, empty, other_ready, sends = run(scenario)
    assert (ready, text, empty, other_ready) == (b"\x01\x00", b"HOMED 3\r", b"\x00\x00",
                                                 b"\x00\x00")
    assert sends == [(1, "HOMED 3")]


def test_spec_5_1_i64_0_line_comes_ahead_of_the_next_reply_up_to_its_ack() -> None:
    async def scenario(handle, port):
        c = await Client.connect(port)
        await _load(c, 0)
        await c.ask("ENA PLC 1")
        first = await c.ask("P1")
        second = await c.ask("P1")
        await c.close()
        return first, second

    assert run(scenario) == (b"HOMED 3\r0\r\x06", b"0\r\x06")


def test_tsrm_p67_i64_1_stx_line_is_returned_alone_and_the_reply_waits() -> None:
    async def scenario(handle, port):
        c = await Client.connect(port)
        await _load(c, 1)
        await c.ask("ENA PLC 1")
        message = await c.ask("P7=5 P7")
        reply = await c.send(GETBUFFER)
        await c.close()
        return message, reply

    assert run(scenario) == (b"\x02HOMED 3\r", b"5\r\x06")
