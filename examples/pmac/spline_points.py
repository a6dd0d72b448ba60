"""The same corner points as SPLINE1 (cubic B-spline, TUM p290) and as blended LINEAR moves.

Run: ``.venv/bin/python examples/pmac/spline_points.py [out.png]``. Six XY points, 100 ms per
segment (``TM100``): the spline passes *inside* the points (each way-point is
``(P[i-1] + 4·P[i] + P[i+1]) / 6``) with velocity and acceleration continuous, and adds a
zero-distance segment at each end, so 6 points take (6 + 2) × 100 = 800 ms from rest to rest.
The LINEAR run (TA50) cuts each corner over its 50 ms blend instead. Prints both durations and
each spline way-point's distance from its programmed point; plots the two paths.
"""

from __future__ import annotations

import sys

from motionsim.sim.pmac import PmacController

POINTS = [(10, 0), (10, 10), (20, 10), (20, 0), (30, 0), (30, 10)]
SEGMENT_MS = 100


def run(mode: str) -> tuple[PmacController, list[tuple[float, float, float]]]:
    """Run the points in ``mode`` ("SPLINE1" or "LINEAR"); samples ``(t, X, Y)`` every 2 ms."""
    c = PmacController("pmac", {})
    c.define_rotary(1, 100)
    header = f"ABS {mode} TM{SEGMENT_MS}" + (" TA50 TS0" if mode == "LINEAR" else "")
    c.load_lines(1, [header] + [f"X{x} Y{y}" for x, y in POINTS])
    c.run(1)
    samples: list[tuple[float, float, float]] = []

    def sampler():
        while True:
            p = c.positions(1)
            samples.append((c.env.now, p.get("X", 0.0), p.get("Y", 0.0)))
            yield c.env.timeout(0.002)

    c.env.process(sampler())
    c.env.run(until=1.5)
    return c, samples


def duration(c: PmacController) -> float:
    """Seconds from the first move's start to the last move's end."""
    return c.log.events("move_end")[-1].t - c.log.events("move_start")[0].t


def main(out: str | None = None) -> None:
    spline, linear = run("SPLINE1"), run("LINEAR")
    print(f"SPLINE1: {duration(spline[0]) * 1000:.1f} ms for {len(POINTS)} points "
          f"((N + 2) x {SEGMENT_MS} ms); LINEAR: {duration(linear[0]) * 1000:.1f} ms")
    pts = [(0, 0), *POINTS, POINTS[-1]]
    for i in range(1, len(pts) - 1):
        wp = [(pts[i - 1][k] + 4 * pts[i][k] + pts[i + 1][k]) / 6 for k in (0, 1)]
        print(f"point {pts[i]}: way-point ({wp[0]:.2f}, {wp[1]:.2f})")
    if out:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(7, 3.4))
        for label, (_, s) in (("SPLINE1 TM100", spline), ("LINEAR TM100 TA50", linear)):
            ax.plot([x for _, x, _ in s], [y for _, _, y in s], label=label)
        ax.plot([0] + [x for x, _ in POINTS], [0] + [y for _, y in POINTS], "k.", label="points")
        ax.set_xlabel("X")
        ax.set_ylabel("Y")
        ax.set_aspect("equal")
        ax.set_title("SPLINE1 passes inside the points; LINEAR blends the corners")
        ax.legend(loc="upper left", fontsize=8)
        fig.tight_layout()
        fig.savefig(out, dpi=90)
        print(f"wrote {out}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
