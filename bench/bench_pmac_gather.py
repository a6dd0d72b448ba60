"""PMAC data gathering overhead: a rotary stream with 8 sources gathered every servo cycle,
against the same stream without gathering (issue 34: at most 2x).

Four motors (``#1->X`` .. ``#4->A``) follow a stream of 5-ms blended 4-axis moves for
``simulated_seconds`` (default 10); the gathered run sets I5001-I5008 to the commanded and
actual positions of the four motors (48-bit registers), I5050 = $FF, I5049 = 1, I5000 = 1
(wrap: the buffer of all free memory holds ~8 000 of the ~22 600 samples) and issues GATHER
before the stream starts, then reads the gather buffer (inside the timed span: the samples
are computed when read; the REST / CSV formatting of a recording is left out, as before);
the plain run sends the same set-up with ENDGATHER in GATHER's
place. The two runs alternate, best of ``repeat`` each.

Prints wall seconds of each and their ratio, writes ``bench/results/pmac_gather.json``
(ratio ``gather_vs_plain``, target <= 2.0 in bench/targets.py).

Run: ``.venv/bin/python bench/bench_pmac_gather.py [simulated_seconds] [repeat]``.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from motionsim.sim.pmac import PmacController  # noqa: E402

from bench.results import write  # noqa: E402

SOURCES = [f"${0x800088 + 0x80 * m + off:06X}" for m in range(4) for off in (0, 3)]


def _cmd(c: PmacController, text: str) -> str:
    reply = c.terminal(text)
    while not reply.done:
        c.env.step()
    assert reply.error is None, (text, reply.error)
    return reply.reply


def run(sim_s: float, gather: bool) -> dict:
    c = PmacController("bench")
    _cmd(c, "&1 #1->X #2->Y #3->Z #4->A")
    c.define_rotary(1, 600)
    for n, spec in enumerate(SOURCES, 1):
        _cmd(c, f"I{5000 + n}={spec}")
    _cmd(c, "I5050=$FF I5051=0 I5049=1 I5000=1")
    _cmd(c, "DEFINE GATHER")
    # The plain run sends ENDGATHER (nothing to end) where the gathered one sends GATHER: the
    # same commands at the same instants, so the processor model is in the same state when
    # the stream starts (whether it sleeps depends on when the last command's background
    # cycle ended, and an awake model costs as much as the gathering).
    _cmd(c, "GATHER" if gather else "ENDGATHER")
    c.load_lines(1, ["TA1 TS0 TM5"])
    c.run(1)
    rot = c.coord_system(1).rotary
    assert rot is not None
    batches = [[f"X{i} Y{i / 2} Z{-i} A{i % 7}"] for i in range(1000)]
    lines = [0]

    def host():
        i = 0
        while True:
            if not rot.breq:
                yield c.wait_breq(1)
            c.load_lines(1, batches[i % 1000])
            i += 1
            lines[0] = i

    c.env.process(host())
    t0 = time.perf_counter()
    c.env.run(until=c.env.now + sim_s)
    # timed: the gatherer computes its samples when the buffer is read
    rec = c.gather.recording() if gather else None
    wall = time.perf_counter() - t0
    return {"wall_s": wall, "lines": lines[0], "events": c.log.last_seq,
            "samples_held": len(rec.cycles) if rec else 0,
            "sample_span_cycles": (rec.cycles[-1] - rec.cycles[0] + 1) if rec else 0}


def main() -> None:
    sim_s = float(sys.argv[1]) if len(sys.argv) > 1 else 10.0
    repeat = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    plain, gathered = [], []
    for _ in range(repeat):
        plain.append(run(sim_s, False))
        gathered.append(run(sim_s, True))
    p = min(plain, key=lambda r: r["wall_s"])
    g = min(gathered, key=lambda r: r["wall_s"])
    ratio = g["wall_s"] / p["wall_s"]
    print(f"pmac stream {sim_s:.0f} simulated s: plain {p['wall_s']:.2f} s wall "
          f"({p['lines']:,} lines), 8 sources gathered every servo cycle {g['wall_s']:.2f} s "
          f"wall ({g['lines']:,} lines, {g['samples_held']:,} samples held): "
          f"{ratio:.2f}x (target <= 2.0; best of {repeat})")
    path = write("pmac_gather", figures={"gathered": g, "simulated_s": sim_s},
                         references={"plain": p}, ratios={"gather_vs_plain": ratio})
    print(f"  -> {path}")


if __name__ == "__main__":
    main()
