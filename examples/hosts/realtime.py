"""Way 3 — realtime with a factor: an unmodified host, in its own thread, polling.

The host knows nothing of motionsim's clock: it polls BREQ, sleeps between polls in wall time
and writes when asked. The clock runs simulated time at ``factor`` × wall time, so 60
simulated seconds take 60 / factor wall seconds. Wall-clock jitter reaches the log: two runs
give the same program, not the same instants (use way 1 or 2 for byte-identical logs).

Run: ``.venv/bin/python examples/hosts/realtime.py [delay_s]`` (``delay_s`` in simulated
seconds: the host sleeps ``delay_s / factor`` wall seconds before each write; 5.0 is beyond
what its I16 lines cover).
"""

from __future__ import annotations

import threading
import time
from typing import Any

from motionsim.app.client import MotionSimClient

try:
    from .streamer import Streamer, main
except ImportError:  # run as a script
    from streamer import Streamer, main  # type: ignore[no-redef]

SIM_S = 60.0
FACTOR = 10.0
#: A wall-clock host needs margin for the operating system's scheduling: 20 lines (~2 s
#: simulated, 0.2 s wall at factor 10) ahead when BREQ rises.
I16, I17 = 20, 40
#: Wall seconds between two polls: 20 simulated ms at factor 10, far below the ~0.5 s I16 covers.
POLL_S = 0.002


class PollingStreamer(threading.Thread):
    """An ordinary host: poll, sleep, write. ``stop`` ends it; errors reach the test."""

    def __init__(self, url: str, delay_wall_s: float = 0.0) -> None:
        super().__init__(name="polling-streamer", daemon=True)
        self.client = MotionSimClient(url)
        self.delay_wall_s = delay_wall_s
        self.stop = threading.Event()
        self.error: BaseException | None = None
        #: The longest wall time between two polls, less the deliberate delay: how long the
        #: operating system (or a pause of the whole process) kept this host from looking.
        self.worst_gap_s = 0.0

    def run(self) -> None:
        streamer = Streamer(self.client, "pmac", i17=I17)
        try:
            last = time.monotonic()
            while not self.stop.is_set():
                delayed = 0.0
                if streamer.breq():
                    if self.delay_wall_s:
                        time.sleep(self.delay_wall_s)
                        delayed = self.delay_wall_s
                    streamer.refill()
                self.stop.wait(POLL_S)
                now = time.monotonic()
                self.worst_gap_s = max(self.worst_gap_s, now - last - delayed)
                last = now
        except BaseException as exc:
            self.error = exc
        finally:
            self.client.close()

    def join_checked(self, timeout: float = 30.0) -> None:
        self.stop.set()
        self.join(timeout)
        if self.error is not None:
            raise self.error


def run(ms: MotionSimClient, delay_s: float = 0.0, sim_s: float = SIM_S,
        factor: float = FACTOR, host_report: dict[str, float] | None = None
        ) -> list[dict[str, Any]]:
    """Stream for ``sim_s`` simulated seconds at ``factor``; the controller's event log.

    ``host_report``, if given, receives ``worst_gap_s``: the host's longest wall-clock lapse
    between two polls. A lapse beyond the wall time its I16 lines cover starves any host,
    however correct: that is the machine, not the host (the test reruns such a run)."""
    ms.create_controller("pmac", id="pmac", clock="realtime", factor=factor,
                         config={"i16": I16, "i17": I17})
    ms.define_rotary("pmac", 1, 600)
    host = PollingStreamer(ms.url, delay_s / factor)
    host.start()
    try:
        t0 = ms.clock("pmac").t
        while (left := sim_s - (ms.clock("pmac").t - t0)) > 0:
            time.sleep(min(0.2, left / factor))
        ms.set_clock("pmac", paused=True)   # freeze time before reading the log
    finally:
        host.join_checked()
        if host_report is not None:
            host_report["worst_gap_s"] = host.worst_gap_s
    return ms.all_events("pmac")


if __name__ == "__main__":
    main(run, f"realtime x{FACTOR:g}", SIM_S)
