"""One protocol port cannot starve the others (issue 33 item 6; api/trio_modbus/server.py).

A Modbus master that pipelines thousands of FC3 reads in one write and never reads the
replies used to have a whole 64-KB chunk answered in one go on the event loop (and its
replies buffered whole); the PMAC and Trio ports timed out meanwhile. Now a connection answers
``FAIR_SHARE`` requests per turn, waits for its replies to drain (back-pressure on that
connection only) and lets the loop serve everyone else. Asserted as interleaving (how often
another task ran while the requests were answered), not durations.
"""

from __future__ import annotations

import asyncio
import struct

from motionsim.api.trio_modbus import server as modbus_server
from motionsim.api.trio_modbus.server import serve_modbus
from motionsim.api.wire import FAIR_SHARE

from tests.api.wire_helpers import connect, run_served

N = 5000
FC3 = b"".join(struct.pack(">HHHBBHH", tid, 0, 6, 1, 3, 0, 125) for tid in range(N))


def test_a_pipelining_master_that_never_reads_shares_the_loop(monkeypatch) -> None:
    answered = 0
    real = modbus_server.answer

    def counting(handle, codec, request):
        nonlocal answered
        answered += 1
        return real(handle, codec, request)

    monkeypatch.setattr(modbus_server, "answer", counting)

    async def scenario(handle, port):
        reader, writer = await connect(port)
        writer.transport.set_write_buffer_limits(high=1 << 24)  # all N go out at once
        writer.write(FC3)
        await writer.drain()
        seen: list[int] = []
        for _ in range(3000):  # another client of the loop: one look per turn
            seen.append(answered)
            await asyncio.sleep(0)
        other = await asyncio.wait_for(asyncio.to_thread(lambda: 1), 5)  # the loop is alive
        writer.close()
        return seen, other

    seen, other = run_served(serve_modbus, "trio", "trio", scenario)
    progress = sorted(set(seen) - {0})
    # the other task ran between the answers of one chunk, FAIR_SHARE at a time ...
    assert len(progress) >= 20
    assert all(b - a <= FAIR_SHARE for a, b in zip(progress, progress[1:], strict=False))
    assert other == 1
