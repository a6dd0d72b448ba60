"""The PMAC Ethernet server over real loopback sockets, on a stand-in PMAC with a virtual clock.

Each TCP connection is a host port (spec pmac.md §1.1 "one port only", TUM p48); every line
goes through ``handle.command`` — the same path as the REST terminal.
"""

from __future__ import annotations

import asyncio

import pytest
from motionsim.api.pmac_ethernet.protocol import VR, VR_DOWNLOAD, getresponse, pack_request
from motionsim.api.pmac_ethernet.server import serve_pmac

from tests.api.wire_helpers import connect, run_served

TIMEOUT = 2.0


class Client:
    def __init__(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        self.reader, self.writer = reader, writer

    @classmethod
    async def connect(cls, port: int) -> Client:
        return cls(*await connect(port))

    async def send(self, packet: bytes, n: int | None = None) -> bytes:
        self.writer.write(packet)
        await self.writer.drain()
        if n is not None:
            return await asyncio.wait_for(self.reader.readexactly(n), TIMEOUT)
        return await asyncio.wait_for(self.reader.read(4096), TIMEOUT)

    async def ask(self, command: str | bytes) -> bytes:
        return await self.send(getresponse(command))

    async def closed_by_server(self) -> bool:
        return await asyncio.wait_for(self.reader.read(1), TIMEOUT) == b""

    async def close(self) -> None:
        self.writer.close()
        await self.writer.wait_closed()


def run(scenario, kind: str = "wirepmac"):
    """Run ``scenario(handle, port)`` against a served PMAC (the stand-in unless ``kind`` says
    otherwise) on a virtual clock."""
    return run_served(serve_pmac, kind, "pmac", scenario)


def test_dls_pmaclib_connect_handshake_switches_framing_to_i3_2() -> None:
    """Power-on I3=1 frames ``<LF>DATA<CR><LF>``; ``i6=1 i3=2 ver`` then answers
    ``1.947  \\r\\x06`` (the reply dls-pmaclib's regex requires), framed after the line ran."""

    async def scenario(handle, port):
        c = await Client.connect(port)
        before = await c.ask("ver")
        handshake = await c.ask("i6=1 i3=2 ver")
        cid = await c.ask("cid")
        await c.close()
        return before, handshake, cid

    before, handshake, cid = run(scenario)
    assert before == b"\n1.947  \r\n"
    assert handshake == b"1.947  \r\x06"
    assert cid == b"603382\r\x06"


def test_each_reply_is_framed_by_the_i3_i6_in_force_after_its_line_ran() -> None:
    """Spec §2.1 / §2.2 on the real PMAC: I3 / I6 written over the wire, over REST or by a
    later line in the same request change the framing of the very next reply (the session
    keeps the pair only while no I-variable changes)."""

    async def scenario(handle, port):
        c = await Client.connect(port)
        out = [await c.ask("I3=2 I6=1"), await c.ask("I16"), await c.ask("I3=0 I16")]
        await handle.command("I3=3")  # another port (REST) changes it
        out += [await c.ask("I16"), await c.ask("I6=3 I3=2"), await c.ask("XYZ"),
                await c.ask("I6=0"), await c.ask("XYZ")]
        await c.close()
        return out

    assert run(scenario, kind="pmac") == [
        b"\x06", b"5\r\x06", b"5\r", b"\n5\r\x06", b"\x06", b"\x07\rERR003\r", b"\x06", b"\x07"]


def test_a_line_over_tcp_goes_through_the_controller_in_virtual_time() -> None:
    """The virtual clock runs forward to the reply instant (0.5 ms background), and the line is
    in the controller's event log like a REST terminal line."""

    async def scenario(handle, port):
        c = await Client.connect(port)
        await c.ask("I16")
        await c.ask("I17")
        await c.close()
        return [(e.t, e["command"]) for e in handle.controller.log.events("wire_command")]

    assert run(scenario) == [(0.0, "I16"), (0.0005, "I17")]


def test_only_one_connection_may_hold_the_buffers_open() -> None:
    """OPEN from a second port while another holds a buffer open → ERR007; a buffered line
    from a port with no open buffer → ERR005; nothing stored. Closing the holder's connection
    releases the buffer."""

    async def scenario(handle, port):
        a, b = await Client.connect(port), await Client.connect(port)
        await a.ask("i3=2")
        got = [await a.ask("OPEN ROT"), await b.ask("X1"), await b.ask("OPEN ROT"),
               await a.ask("X2")]
        await a.close()
        await asyncio.sleep(0.05)
        got.append(await b.ask("OPEN ROT"))
        await b.close()
        return got, handle.controller.stored

    got, stored = run(scenario)
    assert got == [b"\x06", b"\x07ERR005\r", b"\x07ERR007\r", b"\x06", b"\x06"]
    assert stored == ["X2"]


def test_epics_flush_then_getresponse_answers_one_line_per_query() -> None:
    """EPICS pmacAsynIPPort: FLUSH (1 byte back, '@'), then GETRESPONSE ``cmd\\n`` with up to
    40 space-separated queries, one ``\\r``-terminated line each, one ACK."""

    async def scenario(handle, port):
        c = await Client.connect(port)
        await c.ask("i3=2 i6=1")
        flush = await c.send(bytes.fromhex("40b3000000000000"), 1)
        queries = " ".join(f"I{n}" for n in range(100, 140))
        reply = await c.ask(queries + "\n")
        probe = await c.ask("\n")
        await c.close()
        return flush, reply, probe

    flush, reply, probe = run(scenario)
    assert flush == b"@"
    assert reply == b"0\r" * 40 + b"\x06"
    assert probe == b"\x06"


def test_writebuffer_download_reports_failing_line_and_stops_there() -> None:
    async def scenario(handle, port):
        c = await Client.connect(port)
        body = b"OPEN ROT\x00X1\x00BOGUS\x00X2\x00CLOSE\x00"
        status = await c.send(pack_request(VR_DOWNLOAD, VR.PMAC_WRITEBUFFER, payload=body), 4)
        await c.close()
        return status, handle.controller.stored

    status, stored = run(scenario)
    assert status == b"\x02\x00\x03\x80"  # line 2 (0-based), ERR003
    assert stored == ["X1"]


def test_disconnect_mid_request_stores_nothing_and_server_keeps_serving() -> None:
    async def scenario(handle, port):
        c = await Client.connect(port)
        packet = pack_request(VR_DOWNLOAD, VR.PMAC_WRITEBUFFER,
                              payload=b"OPEN ROT\x00X1\x00X2\x00CLOSE\x00")
        c.writer.write(packet[:-5])
        await c.writer.drain()
        await c.close()
        await asyncio.sleep(0.05)
        d = await Client.connect(port)
        again = await d.ask("i3=2 ver")
        await d.close()
        return again, handle.controller.stored, handle.controller.holder

    again, stored, holder = run(scenario)
    assert again == b"1.947  \r\x06" and stored == [] and holder is None


def test_broken_stream_closes_only_that_connection() -> None:
    async def scenario(handle, port):
        good, bad = await Client.connect(port), await Client.connect(port)
        bad.writer.write(bytes.fromhex("40aa000000000000"))
        closed = await bad.closed_by_server()
        answer = await good.ask("i3=2 cid")
        await good.close()
        return closed, answer

    assert run(scenario) == (True, b"603382\r\x06")


def test_bytes_above_127_answer_err004_and_are_not_executed() -> None:
    async def scenario(handle, port):
        c = await Client.connect(port)
        await c.ask("i3=2")
        got = await c.ask(b"I16=\xff")
        await c.close()
        return got, [cmd for _, _, cmd in handle.controller.commands]

    got, commands = run(scenario)
    assert got == b"\x07ERR004\r" and commands == ["i3=2"]


def test_long_reply_is_fetched_with_getbuffer_like_dls_pmaclib() -> None:
    async def scenario(handle, port):
        c = await Client.connect(port)
        await c.ask("i3=2")
        first = await c.ask(" ".join(["ver"] * 200))  # 200 × 8 bytes + ACK = 1601 bytes
        rest = await c.send(bytes.fromhex("c0c5000000000800"))
        ready = await c.send(bytes.fromhex("c0c2000000000002"), 2)
        await c.close()
        return first, rest, ready

    first, rest, ready = run(scenario)
    # 8-byte lines put a CR at byte 1400: the piece carries one byte more (never ends in CR)
    assert len(first) == 1401 and first + rest == b"1.947  \r" * 200 + b"\x06"
    assert ready == b"\x00\x00"


def test_watchdog_tripped_pmac_does_not_answer() -> None:
    async def scenario(handle, port):
        c = await Client.connect(port)
        c.writer.write(getresponse("HALT"))
        ready = await c.send(bytes.fromhex("c0c2000000000002"), 2)
        await c.close()
        return ready

    assert run(scenario) == b"\x00\x00"


def test_pending_reply_is_given_up_when_the_host_disconnects() -> None:
    async def scenario(handle, port):
        c = await Client.connect(port)
        await c.ask("OPEN ROT")
        c.writer.write(getresponse("NEVER"))
        await c.writer.drain()
        await asyncio.sleep(0.05)
        await c.close()
        for _ in range(50):
            if handle.controller.holder is None:
                break
            await asyncio.sleep(0.01)
        return handle.controller.holder

    assert run(scenario) is None


@pytest.mark.parametrize("n", [3])
def test_connections_are_served_concurrently(n: int) -> None:
    async def scenario(handle, port):
        clients = [await Client.connect(port) for _ in range(n)]
        replies = await asyncio.gather(*(c.ask("i3=2 cid") for c in clients))
        for c in clients:
            await c.close()
        return replies

    assert run(scenario) == [b"603382\r\x06"] * n


def test_rest_terminal_is_one_more_port_for_the_one_open_buffer_rule() -> None:
    """Issue 6 §3 on the real ``pmac`` kind: the REST terminal holds the buffers open, so a TCP
    connection's OPEN → ERR007 and its buffered line → ERR005, nothing stored; after the REST
    port's CLOSE the TCP port may open them."""

    async def scenario(handle, port):
        for cmd in ("&1 DEFINE ROT 100", "OPEN ROT"):
            assert (await handle.command(cmd)).error is None
        c = await Client.connect(port)
        got = [await c.ask("OPEN ROT"), await c.ask("X1")]
        assert (await handle.command("CLOSE")).error is None
        got += [await c.ask("OPEN ROT"), await c.ask("X2"), await c.ask("CLOSE")]
        await c.close()
        return got, [e["text"] for e in handle.controller.log.events("line_loaded")]

    got, loaded = run(scenario, kind="pmac")
    assert got == [b"\x07ERR007\r", b"\x07ERR005\r", b"\x06", b"\x06", b"\x06"]
    assert loaded == ["X2"]
