"""The Trio command-line server over loopback sockets, on a stand-in Trio with a virtual clock.

TN20-16: a move typed at the command line when the buffers are full locks the terminal until
the move is buffered — over TCP, the ``>>`` prompt does not come back until then.
"""

from __future__ import annotations

import asyncio

from motionsim.api.trio_terminal.server import serve_trio

from tests.api.wire_helpers import connect, run_served

TIMEOUT = 2.0


async def read_until_prompt(reader: asyncio.StreamReader) -> bytes:
    return await asyncio.wait_for(reader.readuntil(b">>"), TIMEOUT)


async def nothing_more(reader: asyncio.StreamReader) -> bytes:
    """What arrives within 0.1 s wall (b"" when nothing does)."""
    try:
        return await asyncio.wait_for(reader.read(100), 0.1)
    except TimeoutError:
        return b""


def run(scenario):
    return run_served(serve_trio, "wiretrio", "trio", scenario)


def test_plain_socket_client_gets_echo_reply_and_prompt() -> None:
    async def scenario(handle, port):
        reader, writer = await connect(port)
        writer.write(b"\r\n")
        first = await read_until_prompt(reader)
        writer.write(b"VR(5)=2\r\n? VR(5)\r\nFOO\r\n")
        got = [await read_until_prompt(reader) for _ in range(3)]
        writer.close()
        return first, got

    first, got = run(scenario)
    assert first == b"\r\n>>"
    assert got == [
        b"VR(5)=2\r\n>>",
        b"? VR(5)\r\n2.0000\r\n>>",
        b"FOO\r\n%Command not recognised\r\n>>",
    ]


def test_move_that_cannot_be_buffered_holds_the_prompt_until_buffered() -> None:
    """The prompt after ``MOVE`` comes only when the move is buffered (10 ms simulated later);
    the line typed meanwhile is not even echoed until then, and runs after it."""

    async def scenario(handle, port):
        reader, writer = await connect(port)
        writer.write(b"MOVE(10)\r\n?1\r\n")
        echo = await asyncio.wait_for(reader.readuntil(b"\r\n"), TIMEOUT)
        early = await nothing_more(reader)  # no prompt, no echo of "?1"
        locked = handle.controller.terminal_state()
        handle.clock.advance(0.02)
        rest = [await read_until_prompt(reader) for _ in range(2)]
        writer.close()
        return echo, locked, early, rest, handle.controller.moves

    echo, locked, early, rest, moves = run(scenario)
    assert echo == b"MOVE(10)\r\n"
    assert locked == {"locked": True, "pending": ["MOVE(10)"]}
    assert early == b""
    assert rest == [b">>", b"?1\r\n1.0000\r\n>>"]
    assert moves == [(0.01, "MOVE(10)")]


def test_lock_taken_over_tcp_is_the_shared_process_0_lock() -> None:
    """A second session's line waits behind the first session's pending move (one process 0)."""

    async def scenario(handle, port):
        r1, w1 = await connect(port)
        r2, w2 = await connect(port)
        w1.write(b"MOVE(1)\r\n")
        await asyncio.wait_for(r1.readuntil(b"\r\n"), TIMEOUT)
        w2.write(b"?2\r\n")
        echo2 = await asyncio.wait_for(r2.readuntil(b"\r\n"), TIMEOUT)
        before = await nothing_more(r2)
        handle.clock.advance(0.02)
        after = await read_until_prompt(r2)
        w1.close()
        w2.close()
        return echo2, before, after

    echo2, before, after = run(scenario)
    assert echo2 == b"?2\r\n" and before == b"" and after == b"2.0000\r\n>>"


def test_telnetlib3_style_negotiation_then_command() -> None:
    """A telnet client opening with option negotiation gets answers and a working line."""

    async def scenario(handle, port):
        reader, writer = await connect(port)
        writer.write(bytes([255, 253, 1, 255, 253, 3, 255, 251, 24]) + b"?3\r\n")
        got = await read_until_prompt(reader)
        writer.close()
        return got

    assert run(scenario) == bytes([255, 251, 1, 255, 251, 3, 255, 254, 24]) + b"?3\r\n3.0000\r\n>>"
