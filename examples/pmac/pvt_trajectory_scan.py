"""A trajectory scan: PVT segments computed from a path, streamed into a rotary buffer under BREQ.

Run: ``.venv/bin/python examples/pmac/pvt_trajectory_scan.py [out.png]``. Like the EPICS
``pmac`` trajectory scan (spec §11.1), the host samples a path — here X = 20·sin(2πt/T),
Y = 10·(1 − cos(2πt/T)) — every 20 ms, sends one ``X{pos}:{vel} Y{pos}:{vel}`` line per
BREQ rising edge after a ``PVT20`` header (velocities in units per Isx90 = 1000 ms, i.e.
units/s) and ends with a zero-velocity point. It prints the BREQ / run figures and plots the
commanded path against the programmed points, with the rotary lines ahead.
"""

from __future__ import annotations

import math
import sys

from motionsim.sim.pmac import PmacController

SEGMENT_MS = 20
PERIOD_S = 2.0
POINTS = 200


def path(t: float) -> tuple[float, float, float, float]:
    """Position and velocity (units, units/s) of X and Y at ``t``."""
    w = 2 * math.pi / PERIOD_S
    return (20 * math.sin(w * t), 20 * w * math.cos(w * t),
            10 * (1 - math.cos(w * t)), 10 * w * math.sin(w * t))  # fmt: skip


def lines() -> list[str]:
    out = [f"ABS PVT{SEGMENT_MS}"]
    for i in range(1, POINTS + 1):
        x, vx, y, vy = path(i * SEGMENT_MS / 1000)
        if i == POINTS:
            vx = vy = 0.0  # the last point at rest (as the EPICS program does)
        out.append(f"X{x:.4f}:{vx:.4f} Y{y:.4f}:{vy:.4f}")
    return out


def run() -> tuple[PmacController, list[str]]:
    c = PmacController("pmac", {"i16": 5, "i17": 10})
    for cmd in ("&1 DEFINE ROT 600", "&1 B0", "OPEN ROT"):  # OPEN ROT raises BREQ
        reply = c.terminal(cmd)
        while not reply.done:
            c.env.step()
    c.terminal("CLOSE")
    c.run(1)
    rot = c.coord_system(1).rotary
    program = lines()

    def host():
        for line in program:
            if not rot.breq:
                yield c.wait_breq(1)
            c.load_lines(1, [line])
            yield c.env.timeout(0.001)  # the host's own time per line

    samples: list[tuple[float, dict[str, float]]] = []

    def sampler():  # the commanded position every 2 ms, as a gather would record it
        while True:
            samples.append((c.env.now, c.positions(1)))
            yield c.env.timeout(0.002)

    c.env.process(host())
    c.env.process(sampler())
    c.env.run(until=POINTS * SEGMENT_MS / 1000 + 0.5)
    c.samples = samples  # type: ignore[attr-defined]
    return c, program


def main(out: str | None = None) -> None:
    c, program = run()
    progs = [dict(e.fields) for e in c.log.events("program")]
    starts = c.log.events("move_start")
    ends = c.log.events("move_end")
    print(f"segments executed: {len(ends)} of {POINTS}; program states: "
          f"{[p['state'] for p in progs]}; run-time error: {any('error' in p for p in progs)}")
    print(f"first segment starts {starts[0].t * 1000:.2f} ms, last ends {ends[-1].t * 1000:.2f}"
          f" ms: {(ends[-1].t - starts[0].t) * 1000:.2f} ms for {POINTS} x {SEGMENT_MS} ms")
    print(f"BREQ rising edges: {sum(1 for e in c.log.events('breq') if e['level'])}")
    if out:
        plot(c, out)
        print(f"wrote {out}")


def plot(c: PmacController, out: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    pos = [p for _, p in c.samples]  # type: ignore[attr-defined]
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4.2))
    ax1.plot([p.get("X", 0) for p in pos], [p.get("Y", 0) for p in pos], lw=1.2,
             label="commanded (PVT cubics)")  # fmt: skip
    px = [path(i * SEGMENT_MS / 1000) for i in range(POINTS + 1)]
    ax1.plot([p[0] for p in px], [p[2] for p in px], ".", ms=3, label="programmed points")
    ax1.set_xlabel("X (units)")
    ax1.set_ylabel("Y (units)")
    ax1.set_aspect("equal")
    ax1.legend(loc="upper right", fontsize=8)
    ax1.set_title(f"PVT{SEGMENT_MS} trajectory scan, {POINTS} segments")
    ahead = [(e.t, e["lines_ahead"]) for e in c.log.events("line_loaded")]
    ax2.step([a[0] for a in ahead], [a[1] for a in ahead], where="post", lw=1)
    # the thresholds above the trace (zorder), the axis on the band the stream lives in once
    # the start-up fill is done: I16 - 2 .. I17 + 1
    ax2.axhline(10, ls="--", c="tab:green", lw=1.2, zorder=3, label="I17 = 10")
    ax2.axhline(5, ls="--", c="tab:purple", lw=1.2, zorder=3, label="I16 = 5")
    ax2.set_ylim(3, 11)
    ax2.set_xlabel("simulated time (s)")
    ax2.set_ylabel("lines ahead when a line is loaded")
    ax2.legend(fontsize=8, loc="lower right", framealpha=1)
    ax2.set_title("host under BREQ")
    fig.tight_layout()
    fig.savefig(out, dpi=90)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
