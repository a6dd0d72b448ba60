"""A LINEAR program slowed by the motors' maximum program velocity Ixx16 (TSRM p98) and
acceleration Ixx17 (PSRM p74, TUM p276).

Run: ``.venv/bin/python examples/pmac/velocity_limited_linear.py [out.png]``. X is motor 1
and Y motor 2 at 1000 counts per unit. The same four TM200 moves run three times: with
Ixx16 = 32 counts/ms (the factory value) the moves that ask more than 32 counts/ms of a motor
are made longer, all motors of the CS slowing in proportion so the path stays the same
(Isx13 = 0); with Ixx16 = 1000 they keep their 200 ms. Both of those runs raise Ixx17 to 1000
counts/ms² so only Ixx16 acts. The third keeps the factory Ixx17 = 0.015625 counts/ms²: every
ramp (and every removed stop between the blended moves) must stay under it, so the moves become
much longer. Prints each move's duration, plots X(t).
"""

from __future__ import annotations

import sys

from motionsim.sim.pmac import PmacController

PROGRAM = ["LINEAR ABS TA20 TS0 TM200", "X4 Y1", "X12 Y2", "X13 Y10", "X0 Y0"]


#: Ixx17 that never limits these moves (counts/ms²).
NO_ACCEL_LIMIT = 1000.0


def run(
    ixx16: float, ixx17: float = NO_ACCEL_LIMIT
) -> tuple[PmacController, list[tuple[float, float]]]:
    c = PmacController("pmac", {})
    setup = ("&1 #1->1000X", "&1 #2->1000Y", f"I116={ixx16}", f"I216={ixx16}",
             f"I117={ixx17}", f"I217={ixx17}")  # fmt: skip
    for cmd in setup:
        reply = c.terminal(cmd)
        while not reply.done:
            c.env.step()
    c.define_rotary(1, 100)
    c.load_lines(1, PROGRAM)
    c.run(1)
    samples: list[tuple[float, float]] = []

    def sampler():
        while True:
            samples.append((c.env.now, c.positions(1).get("X", 0.0)))
            yield c.env.timeout(0.002)

    c.env.process(sampler())
    c.env.run(until=6.0)
    return c, samples


def durations(c: PmacController) -> dict[int, float]:
    """Seconds from each move's start to the next move's start (its own move time)."""
    starts = [(e["n"], e.t) for e in c.log.events("move_start")]
    end = c.log.events("move_end")[-1].t
    out = {}
    for i, (n, t) in enumerate(starts):
        out[n] = (starts[i + 1][1] if i + 1 < len(starts) else end) - t
    return out


def main(out: str | None = None) -> None:
    runs = {
        "Ixx16 = 32 cts/ms": run(32),
        "Ixx16 = 1000 cts/ms": run(1000),
        "Ixx16 = 32, Ixx17 = 0.015625 (factory)": run(32, 0.015625),
    }
    for label, (c, _) in runs.items():
        d = durations(c)
        print(f"{label}: " + ", ".join(f"line {n} {s * 1000:.1f} ms" for n, s in d.items()))
    if out:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(8, 3.6))
        for label, (_, s) in runs.items():
            ax.plot([a for a, _ in s], [b for _, b in s], label=label)
        ax.set_xlabel("simulated time (s)")
        ax.set_ylabel("X commanded (units)")
        ax.set_title("TM200 moves, X at 1000 counts/unit: Ixx16 and Ixx17 stretch them")
        ax.legend()
        fig.tight_layout()
        fig.savefig(out, dpi=90)
        print(f"wrote {out}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
