"""Channel 0 is the command line (TN20 "terminal channel 0"; OUTDEVICE, TRM p. 8-130): a
running program's PRINT and its run-time error line reach a telnet session as they are
printed, and the REST terminal returns them in ``output``."""

from __future__ import annotations

import asyncio

from motionsim.api.trio_terminal.server import serve_trio

from tests.api.wire_helpers import connect, run_served

TIMEOUT = 2.0


def test_program_print_and_error_line_are_pushed_to_a_telnet_session() -> None:
    async def scenario(handle, port):
        reader, writer = await connect(port)
        writer.write(b"\r\n")
        await asyncio.wait_for(reader.readuntil(b">>"), TIMEOUT)
        ctrl = handle.controller
        handle.apply(ctrl.store_program, "HELLO", 'PRINT "hello"\nWA(10)\nVR(1)=1/0\n')
        handle.apply(ctrl.run_program, "HELLO", 2)
        handle.clock.advance(0.001)
        first = await asyncio.wait_for(reader.readuntil(b"\r\n"), TIMEOUT)
        handle.clock.advance(0.05)
        second = await asyncio.wait_for(reader.readuntil(b"\r\n"), TIMEOUT)
        writer.write(b"? 1\r\n")  # the command line still answers
        after = await asyncio.wait_for(reader.readuntil(b">>"), TIMEOUT)
        writer.close()
        return first, second, after

    first, second, after = run_served(serve_trio, "trio", "t", scenario)
    assert first == b"hello\r\n"
    assert second == b"%[Process 2:Line 3] - Divide by zero\r\n"
    assert after == b"? 1\r\n1.0000\r\n>>"
