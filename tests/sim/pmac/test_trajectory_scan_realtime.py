"""The trajectory scan (test_trajectory_scan.py) on a realtime clock at factor 1: the host
(trajectory/host.py) runs in a thread of its own, as the EPICS driver does, and talks to the
card through the controller handle while the clock runs the program in wall time; it fills
the idle half while the other one executes."""

from __future__ import annotations

import asyncio
import time

from motionsim.app.registry import Registry

from tests.sim.pmac.test_trajectory_scan import PROGRAM
from tests.sim.pmac.trajectory.host import ScanHost, points


def test_trajectory_scan_completes_on_a_realtime_clock():
    async def main():
        reg = Registry()
        await reg.start()
        h = reg.add("pmac", "p", clock="realtime", factor=1.0)
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
            end = time.monotonic() + 20
            status = total = 1
            while time.monotonic() < end:
                time.sleep(0.02)
                status, _i, _c, total = host.poll()
                if status != 1:
                    break
            return status, total, host.log

        result = await loop.run_in_executor(None, drive)
        events = h.controller.log.events("mvar")
        await reg.close()
        return result, [e["value"] for e in events if e["name"] == "M4034"]

    (status, total, log), statuses = asyncio.run(main())
    assert (status, total) == (2, 120)
    assert log.count(("fill", 0)) == 2 and ("fill", 1) in log
    assert statuses[-2:] == [1, 2]
