"""PMAC with PLCs: simulated-to-wall ratio with 4 PLCs enabled and a rotary stream running.

The card runs I5=3 with PLC 0 (10 statements, every RTI) and background PLCs 1-3 (a counter,
an IF/ELSE on an M-variable, a WHILE that waits on a P-variable), while a host process streams
``X{i}`` lines (5 ms blended moves, ``TA1 TS0 TM5``) into a 600-word rotary buffer on BREQ
and polls ``PR`` through the terminal every 10 ms. Everything the processor model does is in
the figure: PLC 0 at ~753 Hz, one background scan per servo cycle (~2 259 Hz), host replies,
move planning and execution.

Prints simulated seconds per wall second (the ratio; > 1 = faster than real time), PLC scan
counts, the load figure, and writes ``bench/results/pmac_plc.json``.

Run: ``.venv/bin/python bench/bench_pmac_plc.py [simulated_seconds] [repeat]``.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from motionsim.sim.pmac import PmacController  # noqa: E402

PLC0 = "\n".join(["M1=M1+1"] + [f"P{20 + i}=P{20 + i}+1" for i in range(9)])
PLC1 = "P1=P1+1\nP2=P1*2"
PLC2 = "IF (M1>P3)\nM2=1\nP3=M1+100\nELSE\nM2=0\nENDIF"
PLC3 = "WHILE (P5=0)\nP6=P6+1\nENDWHILE\nP5=0"


def run(sim_s: float) -> dict:
    c = PmacController("bench")
    reply = c.terminal("&1 #1->X")  # one active motor: ~1 % servo load (seed 003)
    while not reply.done:
        c.env.step()
    c.set_variable("I5", 3)
    for n, text in enumerate((PLC0, PLC1, PLC2, PLC3)):
        c.plcs.load(n, text)
    c.plcs.set_enabled((0, 1, 2, 3), True)
    c.define_rotary(1, 600)
    c.load_lines(1, ["TA1 TS0 TM5"])
    c.run(1)
    rot = c.coord_system(1).rotary
    batches = [[f"X{i}"] for i in range(1000)]
    lines = [0]
    polls = [0]

    def host():
        i = 0
        while True:
            if not rot.breq:
                yield c.wait_breq(1)
            c.load_lines(1, batches[i % 1000])
            i += 1
            lines[0] = i

    def poller():
        while True:
            yield c.env.timeout(0.01)
            c.terminal("PR")
            polls[0] += 1

    c.env.process(host())
    c.env.process(poller())
    t0 = time.perf_counter()
    c.env.run(until=sim_s)
    wall = time.perf_counter() - t0
    plcs = {p["plc"]: p["scans"] for p in c.plcs.to_list()}
    return {
        "simulated_s": sim_s,
        "wall_s": wall,
        "ratio": sim_s / wall,
        "lines": lines[0],
        "lines_per_wall_s": lines[0] / wall,
        "pr_polls": polls[0],
        "plc_scans": plcs,
        "events": c.log.last_seq,
        "cpu": c.status()["cpu"],
        "watchdog_tripped": c.halted,
    }


def main() -> None:
    sim_s = float(sys.argv[1]) if len(sys.argv) > 1 else 60.0
    repeat = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    runs = [run(sim_s) for _ in range(repeat)]
    res = max(runs, key=lambda r: r["ratio"])
    res["all_ratios"] = [r["ratio"] for r in runs]
    print(f"pmac + 4 PLCs + rotary stream: {res['ratio']:.1f} simulated s per wall s "
          f"({sim_s:.0f} s simulated in {res['wall_s']:.2f} s wall; best of {repeat})")
    print(f"  lines streamed {res['lines']:,} ({res['lines_per_wall_s']:,.0f}/wall s), "
          f"PR polls {res['pr_polls']:,}, events {res['events']:,}")
    print(f"  PLC scans {res['plc_scans']}")
    cpu = res["cpu"]
    print(f"  load: servo {cpu['servo']:.3f}  rti {cpu['rti']:.3f}  "
          f"background {cpu['background']:.3f}  cycle {cpu['background_cycle_s'] * 1e6:.0f} µs; "
          f"watchdog tripped: {res['watchdog_tripped']}")
    out = Path(__file__).parent / "results"
    out.mkdir(exist_ok=True)
    (out / "pmac_plc.json").write_text(json.dumps(res, indent=2))


if __name__ == "__main__":
    main()
