"""A kinematic CS against a plain CS: the same 10 000-segment program, simulated seconds per
wall second (issue 24: target ≥ 0.3).

Both runs: PROG 1 of 1 000 blended LINEAR moves of 100 ms (``TA20 TS0``) with Isx13 = 10 ms,
so 10 000 segments (100 simulated s). The plain CS has ``#1->1000X #2->1000Y``; the kinematic
CS has ``#1->I #2->I``, Isx50 = 1 and a two-jack forward / inverse pair (six arithmetic
statements; the inverse is compiled once, sim/pmac/kinematics/subroutine.py). In both, a host
process reads both motors' positions at every segment instant (``motor_position``), so the
kinematic run computes the inverse for every segment; the plain run does the same reads.
The two are interleaved, best of ``repeat`` kept; the ratio is kinematic / plain.

Run: ``.venv/bin/python bench/bench_pmac_kinematics.py [repeat]``.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from motionsim.sim.pmac import PmacController  # noqa: E402

from bench import results  # noqa: E402

MOVES = 1000
MOVE_MS = 100
SEGMENT_MS = 10
KINEMATICS = [
    "&1 OPEN FORWARD CLEAR", "Q7=(P1+P2)/2000 Q8=(P2-P1)/1000", "CLOSE",
    "&1 OPEN INVERSE CLEAR", "Q20=Q8/2", "P1=(Q7-Q20)*1000", "P2=(Q7+Q20)*1000", "CLOSE",
]


def _ok(c: PmacController, text: str) -> None:
    reply = c.terminal(text)
    while not reply.done:
        c.env.step()
    assert reply.error is None, (text, reply.error)


def run(kinematic: bool) -> dict:
    c = PmacController("bench")
    if kinematic:
        _ok(c, "&1 #1->I #2->I")
        for line in KINEMATICS:
            _ok(c, line)
        _ok(c, "I5150=1")
    else:
        _ok(c, "&1 #1->1000X #2->1000Y")
    _ok(c, f"I5113={SEGMENT_MS}")
    _ok(c, "OPEN PROG 1 CLEAR")
    _ok(c, f"LINEAR ABS TA20 TS0 TM{MOVE_MS}")
    for i in range(MOVES):
        _ok(c, f"X{(i % 50) * 0.1:.1f} Y{((i * 7) % 30) * 0.05 - 0.75:.2f}")
    _ok(c, "CLOSE")
    reads = [0]
    seg = SEGMENT_MS / 1000.0

    def observer():
        while True:
            yield c.env.timeout(seg)
            now = c.env.now
            c.motor_position(1, now)
            c.motor_position(2, now)
            reads[0] += 1

    t_start = c.env.now
    _ok(c, "&1 B1 R")
    c.env.process(observer())
    sim_s = MOVES * MOVE_MS / 1000.0 + 1.0
    t0 = time.perf_counter()
    c.env.run(until=t_start + sim_s)
    wall = time.perf_counter() - t0
    assert c.coord_system(1).state == "stopped", c.coord_system(1).state
    return {"simulated_s": sim_s, "wall_s": wall, "ratio": sim_s / wall, "reads": reads[0],
            "segments": MOVES * MOVE_MS // SEGMENT_MS}


def main() -> None:
    repeat = int(sys.argv[1]) if len(sys.argv) > 1 else 3
    kin, plain = [], []
    for _ in range(repeat):
        plain.append(run(False))
        kin.append(run(True))
    best_k = max(kin, key=lambda r: r["ratio"])
    best_p = max(plain, key=lambda r: r["ratio"])
    ratio = best_k["ratio"] / best_p["ratio"]
    print(f"kinematic CS: {best_k['ratio']:.1f} simulated s per wall s; plain CS: "
          f"{best_p['ratio']:.1f}; kinematic / plain = {ratio:.2f} (target >= 0.3; "
          f"{best_k['segments']:,} segments, {best_k['reads']:,} position reads, "
          f"best of {repeat})")
    results.write("pmac_kinematics", figures={"kinematic": best_k},
                  references={"plain": best_p}, ratios={"kinematic_vs_plain": ratio})


if __name__ == "__main__":
    main()
