"""The trajectory scan (test_trajectory_scan.py) on a realtime clock at factor 1: the host
(examples/pmac/scan_host.py) runs in a thread of its own, as the EPICS driver does, and talks to the
card through the controller handle while the clock runs the program in wall time; it fills
the idle half while the other one executes.

A wall-clock host underruns, however correct, when the machine keeps it from polling for longer
than a half-buffer of points lasts: the clock runs at half of wall speed (a half of 10-ms
points lasts twice as long), and "the scan completes" is asserted when the host's longest
lapse between two polls stayed under half a half-buffer; otherwise only what a stall cannot
falsify (the scan ends, completed or with the underrun status 3, never hangs or misreports)."""

from __future__ import annotations

import asyncio
import time

from motionsim.app.registry import Registry
from motionsim.examples.pmac.scan_host import ScanHost, points

from tests.sim.pmac.test_trajectory_scan import PROGRAM

#: Simulated seconds per wall second: a half-buffer lasts twice its simulated duration.
FACTOR = 0.5


def test_trajectory_scan_completes_on_a_realtime_clock():
    async def main():
        reg = Registry()
        await reg.start()
        h = reg.add("pmac", "p", clock="realtime", factor=FACTOR)
        loop = asyncio.get_running_loop()

        def ask(line: str) -> str:
            reply = asyncio.run_coroutine_threadsafe(h.command(line), loop).result(10)
            assert reply.error is None, (line, reply.error)
            return reply.reply

        def drive() -> tuple[int, int, list]:
            ask("&1 #1->1000X #2->1000Y")
            for line in PROGRAM.read_text().splitlines():
                line = line.split(";")[0].strip()
                if line:
                    ask(line)
            host = ScanHost(ask=ask)
            host.setup()
            host.start(points(120))
            end = time.monotonic() + 60
            status = total = 1
            last, worst = time.monotonic(), 0.0
            while time.monotonic() < end:
                time.sleep(0.02)
                status, _i, _c, total = host.poll()
                now = time.monotonic()
                worst, last = max(worst, now - last), now
                if status != 1:
                    break
            return status, total, host.log, worst, host.length

        result = await loop.run_in_executor(None, drive)
        events = h.controller.log.events("mvar")
        await reg.close()
        return result, [e["value"] for e in events if e["name"] == "M4034"]

    (status, total, log, worst_gap_s, length), statuses = asyncio.run(main())
    half_wall_s = length * 0.010 / FACTOR
    assert statuses[-1] == status and status in (2, 3)   # ended, as the host read it
    assert log[0] == ("fill", 0) and ("fill", 1) in log  # it refilled while running
    if worst_gap_s < half_wall_s / 2:                    # the host kept polling in time
        assert (status, total) == (2, 120)
        assert log.count(("fill", 0)) == 2
        assert statuses[-2:] == [1, 2]
