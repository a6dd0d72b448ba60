"""Way 1 — the test drives the clock: the host's code runs in the test's own control flow.

The clock is virtual: nothing moves unless the test asks. The test runs the simulation to the
next BREQ rising edge (``run-until``), lets ``delay_s`` of simulated time pass for the host's
reaction, and calls the host's ``refill`` itself. No thread, no wall clock: deterministic and
as fast as the CPU allows. Use it when the host's logic can be called step by step.

Run: ``.venv/bin/python examples/hosts/drive_the_clock.py [delay_s]``.
"""

from __future__ import annotations

from typing import Any

from motionsim.app.client import MotionSimClient

try:
    from .streamer import I16, I17, Streamer, main
except ImportError:  # run as a script
    from streamer import I16, I17, Streamer, main  # type: ignore[no-redef]

SIM_S = 60.0


def run(ms: MotionSimClient, delay_s: float = 0.0, sim_s: float = SIM_S,
        reaction_s: float = 0.002) -> list[dict[str, Any]]:
    """Stream for ``sim_s`` simulated seconds; the controller's whole event log."""
    ms.create_controller("pmac", id="pmac", clock="virtual", config={"i16": I16, "i17": I17})
    ms.define_rotary("pmac", 1, 600)
    host = Streamer(ms, "pmac")
    while True:
        if not host.breq():
            left = sim_s - ms.clock("pmac").t
            if left <= 0:
                break
            ms.run_until("pmac", "breq", left, cs=1, level=True)
        t = ms.clock("pmac").t
        if t >= sim_s:
            break
        ms.advance("pmac", min(reaction_s + delay_s, sim_s - t))  # the host's reaction
        if ms.clock("pmac").t >= sim_s:
            break
        host.refill()
    return ms.all_events("pmac")


if __name__ == "__main__":
    main(run, "test drives the clock", SIM_S)
