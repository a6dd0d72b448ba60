"""Way 2 — host-paced: a host in its own thread, against virtual time, deterministically.

The clock runs as fast as the CPU allows while every holder waits, and holds where one is due:
the streamer (holder ``streamer``) is woken at each BREQ rising edge, ``reaction_s`` later in
simulated time, and time stands still while it reads the buffer and writes its lines — however
long that takes its thread. The test is a holder too (``main``, through ``advance``).

Run: ``.venv/bin/python examples/hosts/host_paced.py [delay_s]`` — prints whether the buffer
was kept fed over 60 simulated seconds and how long that took. ``delay_s`` 1.0 (a host slower
than its I16 lines cover) starves the program.
"""

from __future__ import annotations

from typing import Any

from motionsim.app.client import MotionSimClient

try:
    from .streamer import I16, I17, PacedStreamerThread, main
except ImportError:  # run as a script
    from streamer import I16, I17, PacedStreamerThread, main  # type: ignore[no-redef]

SIM_S = 60.0


def run(ms: MotionSimClient, delay_s: float = 0.0, sim_s: float = SIM_S,
        reaction_s: float = 0.002) -> list[dict[str, Any]]:
    """Stream for ``sim_s`` simulated seconds; the controller's whole event log."""
    ms.create_controller("pmac", id="pmac", clock="virtual", config={"i16": I16, "i17": I17})
    ms.define_rotary("pmac", 1, 600)
    # time waits for the streamer and for main (this thread) until main's advance
    ms.host_paced("pmac", "streamer", "main", reaction_s=reaction_s)
    streamer = PacedStreamerThread(ms.host("pmac", "streamer", register=False), delay_s)
    streamer.start()
    try:
        ms.advance("pmac", sim_s)                             # main waits; the host acts
    finally:
        ms.release("pmac", "streamer")                        # its pending wait returns
        streamer.join_checked()
    return ms.all_events("pmac")


if __name__ == "__main__":
    main(run, "host-paced", SIM_S)
