"""The three ways to drive time (examples/hosts/) in wall seconds: what the tests do not assert.

Each way streams the same 60 simulated seconds of 100-ms moves through a fresh in-process
service (``streamer.play``): the wall time it took, the simulated seconds per wall second, and
whether the program was kept fed. For the realtime way (factor 10, a polling host in its own
thread) also the host's longest lapse between two polls, against the wall time its I16 lines
cover: on a loaded machine the lapse, not motionsim, decides whether a wall-clock host keeps up
(tests/examples/test_host_examples.py asserts only what a stalled machine cannot falsify).

Run: ``.venv/bin/python bench/bench_host_modes.py``; writes ``bench/results/host_modes.json``.
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "examples" / "hosts"))

import drive_the_clock  # noqa: E402
import host_paced  # noqa: E402
import realtime  # noqa: E402
import streamer  # noqa: E402

from bench.results import write  # noqa: E402

SIM_S = 60.0


def main() -> None:
    figures: dict[str, dict] = {}
    for name, module in (("drive", drive_the_clock), ("host_paced", host_paced),
                         ("realtime", realtime)):
        report: dict[str, float] = {}
        kwargs = {"host_report": report} if module is realtime else {}
        events, wall = streamer.play(module.run, **kwargs)
        figures[name] = {"wall_s": round(wall, 3), "sim_per_wall": round(SIM_S / wall, 2),
                         "starved": streamer.starved(events), **report}
    cover = realtime.I16 * streamer.MOVE_MS / 1000 / realtime.FACTOR
    figures["realtime"]["cover_wall_s"] = cover
    print(f"{'way':<12}{'wall s':>8}{'sim/wall':>10}  fed")
    for name, f in figures.items():
        print(f"{name:<12}{f['wall_s']:>8.2f}{f['sim_per_wall']:>10.1f}  "
              f"{'no' if f['starved'] else 'yes'}")
    print(f"realtime host's worst lapse {figures['realtime']['worst_gap_s']:.3f} s "
          f"(its I16 lines cover {cover:.3f} s)")
    path = write("host_modes", figures=figures, references={},
                 ratios={f"{k}_sim_per_wall": v["sim_per_wall"] for k, v in figures.items()})
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
