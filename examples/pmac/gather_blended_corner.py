"""The commanded path of a blended corner, recorded by the card's own data gathering.

Run: ``.venv/bin/python examples/pmac/gather_blended_corner.py [out.png]``. X is motor 1 and
Y motor 2 at 1000 counts per unit, Ixx16 / Ixx17 raised so that only TM / TA shape the moves
(as in ``velocity_limited_linear.py``). Two LINEAR moves make a right-angle corner at (10, 0):
``X10`` then ``Y10``, TM200 each with TA100 TS0, so the second move starts blending in 100 ms
before the first ends and the path rounds the corner (TUM p217: LINEAR moves blend over TA).

The set-up is what a tuning tool writes (TSRM p170-171, docs/pmac.md "Data gathering"):
I5001 / I5002 at the motors' commanded positions (D:$000088 and D:$000108, 1/(Ixx08·32)
counts), I5050 = 3, I5049 = 1 (every servo cycle), ``DEFINE GATHER``, ``GATHER``; after the
moves ``ENDGATHER`` and ``LIST GATHER``, decoded as a host decodes a card's answer (each
12-digit word two 24-bit halves, the last six digits first). Prints how close the path comes
to the corner and writes the X-Y path to ``out.png``.
"""

from __future__ import annotations

import math
import sys

from motionsim.sim.pmac import PmacController

PROGRAM = ["LINEAR ABS TA100 TS0 TM200", "X10", "Y10"]
CORNER = (10.0, 0.0)
SETUP = ("&1 #1->1000X", "&1 #2->1000Y",
         "I116=1000 I216=1000 I117=1000 I217=1000",  # Ixx16 / Ixx17 do not stretch the moves
         "I5001=$800088", "I5002=$800108",
         "I5050=3 I5051=0 I5049=1 I5000=0", "DEFINE GATHER 4000", "GATHER")


def cmd(c: PmacController, text: str) -> str:
    reply = c.terminal(text)
    while not reply.done:
        c.env.step()
    if reply.error is not None:
        raise RuntimeError(f"{text}: {reply.error}")
    return reply.reply


def decode(listing: str, sources: int) -> list[tuple[int, ...]]:
    """LIST GATHER of ``sources`` 48-bit sources: one long word (12 hex digits) each."""
    words = [int(tok, 16) for tok in listing.split()]
    signed = [w - (1 << 48) if w >> 47 else w for w in words]
    return [tuple(signed[i:i + sources]) for i in range(0, len(signed), sources)]


def run() -> tuple[PmacController, list[tuple[float, float]]]:
    """Gather the corner; the path in units (X, Y), one point per servo cycle."""
    c = PmacController("pmac", {})
    c.define_rotary(1, 100)  # before the gather buffer: DEFINE ROT needs none (TUM p337)
    for line in SETUP:
        cmd(c, line)
    c.load_lines(1, PROGRAM)
    c.run(1)
    c.env.run(until=1.0)
    cmd(c, "ENDGATHER")
    scale = 1000 * c.vars.I(108) * 32  # counts per unit x 1/(Ixx08*32) count
    path = [(x / scale, y / scale) for x, y in decode(cmd(c, "LIST GATHER"), 2)]
    return c, path


def closest_to_corner(path: list[tuple[float, float]]) -> float:
    return min(math.dist(p, CORNER) for p in path)


def main(out: str | None = None) -> None:
    c, path = run()
    print(f"{len(path)} samples; the path passes {closest_to_corner(path):.3f} units from the "
          f"corner {CORNER}; it ends at ({path[-1][0]:.3f}, {path[-1][1]:.3f})")
    if out:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(4.5, 4.5))
        ax.plot([x for x, _ in path], [y for _, y in path], ".", markersize=2,
                label="gathered commanded position (every servo cycle)")
        ax.plot([0, 10, 10], [0, 0, 10], ":", color="grey", label="programmed corner")
        ax.set_xlabel("X (units)")
        ax.set_ylabel("Y (units)")
        ax.set_aspect("equal")
        ax.legend(loc="upper left", fontsize=7)
        fig.tight_layout()
        fig.savefig(out, dpi=120)
        print(f"wrote {out}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
