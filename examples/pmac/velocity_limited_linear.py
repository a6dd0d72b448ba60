"""A LINEAR program slowed by the motors' maximum program velocity Ixx16 (TSRM p98).

Run: ``.venv/bin/python examples/pmac/velocity_limited_linear.py [out.png]``. X is motor 1
and Y motor 2 at 1000 counts per unit. The same four TM200 moves run twice: with Ixx16 = 32
counts/ms (the factory value) the moves that ask more than 32 counts/ms of a motor are made
longer, all motors of the CS slowing in proportion so the path stays the same (Isx13 = 0);
with Ixx16 = 1000 they keep their 200 ms. Prints each move's duration, plots X(t).
"""

from __future__ import annotations

import sys

from motionsim.sim.pmac import PmacController

PROGRAM = ["LINEAR ABS TA20 TS0 TM200", "X4 Y1", "X12 Y2", "X13 Y10", "X0 Y0"]


def run(ixx16: float) -> tuple[PmacController, list[tuple[float, float]]]:
    c = PmacController("pmac", {})
    for cmd in ("&1 #1->1000X", "&1 #2->1000Y", f"I116={ixx16}", f"I216={ixx16}"):
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
    c.env.run(until=2.5)
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
    runs = {v: run(v) for v in (32, 1000)}
    for v, (c, _) in runs.items():
        d = durations(c)
        print(f"Ixx16 = {v:>4} cts/ms: " + ", ".join(f"line {n} {s * 1000:.1f} ms"
                                                      for n, s in d.items()))  # fmt: skip
    if out:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(8, 3.6))
        for v, (_, s) in runs.items():
            ax.plot([a for a, _ in s], [b for _, b in s], label=f"Ixx16 = {v} counts/ms")
        ax.set_xlabel("simulated time (s)")
        ax.set_ylabel("X commanded (units)")
        ax.set_title("TM200 moves, X at 1000 counts/unit: Ixx16 stretches the fast ones")
        ax.legend()
        fig.tight_layout()
        fig.savefig(out, dpi=90)
        print(f"wrote {out}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
