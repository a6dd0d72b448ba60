"""TUM p249 as a script: plain ``M1=1`` versus synchronous ``M1==1`` between two moves.

Run: ``.venv/bin/python examples/pmac/sync_m_variables.py``. Prints the event log of each
program in servo cycles: the plain write fires when the move to X10 starts (calculation runs
ahead), the synchronous one at the start of the blend into X20.
"""

from __future__ import annotations

from motionsim.sim.pmac import PmacController


def run(middle: str) -> None:
    c = PmacController("pmac")
    c.define_rotary(1, 600)
    c.load_lines(1, ["TM500 TA100 TS0 X10", middle, "X20"])
    c.run(1)
    c.env.run(until=2.0)
    period = c.scheduler.period_s
    print(f"--- X10 / {middle} / X20")
    for e in c.log.events("move_start", "move_end", "mvar"):
        print(f"  cycle {round(e.t / period):5d}  t={e.t * 1000:8.3f} ms  {e.type:10s} "
              f"{dict(e.fields)}")


if __name__ == "__main__":
    run("M1=1")
    run("M1==1")
