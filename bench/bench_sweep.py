"""Sweeps: 64 scenario runs on 2 local worker processes against the same 64 on 1, and the same
rows from a Dask ``LocalCluster``.

Each run is a 15-simulated-second rotary stream (a PMAC, 600-word buffer, 5 ms moves, a BREQ
host with normally distributed latency), swept over I16 (8 values) x lines per interrupt (8
values). The speed-up is the wall time on 1 worker over the wall time on 2 (target ≥ 1.8 on
2 cores: the runs are independent and CPU-bound, so only process start-up and the
machine's other load stand in the way). The rows of all three must be identical: a sweep's
result must not depend on where it ran.

Run: ``.venv/bin/python bench/bench_sweep.py [--no-dask]``; writes ``bench/results/sweep.json``.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from motionsim.app.scenarios.sweep import make_params, points, sweep  # noqa: E402

from bench.results import write  # noqa: E402

RAW = {
    "name": "bench-sweep",
    "seed": 3,
    "duration_s": 15.0,
    "controllers": {"pmac": {"kind": "pmac", "config": {"i16": 5, "i17": 12},
                             "rotary": [{"cs": 1, "size_words": 600}]}},
    "hosts": [{"type": "breq_interrupt",
               "latency": {"dist": "normal", "mean_ms": 2, "sd_ms": 1},
               "lines_per_interrupt": 4,
               "program": {"generate": {"moves": 3000, "move_ms": 5, "axes": 2}}}],
}
GRID = ["controllers.pmac.config.i16=1:8:1", "hosts.0.lines_per_interrupt=1:8:1"]


def _timed(**kw) -> tuple[float, list[dict]]:
    params = make_params(RAW, GRID)
    runs = points(params)
    assert len(runs) == 64
    t0 = time.perf_counter()
    rows = sweep(RAW, params, runs, **kw)
    return time.perf_counter() - t0, rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--no-dask", action="store_true")
    args = ap.parse_args()
    one, rows1 = _timed(workers=1)
    two, rows2 = _timed(workers=2)
    figures = {"runs": 64, "wall_s_1_worker": one, "wall_s_2_workers": two,
               "rows_identical_2_workers": rows1 == rows2,
               "errors": sum(1 for r in rows1 if r.get("error"))}
    print(f"64 runs: 1 worker {one:.2f} s, 2 workers {two:.2f} s: speed-up {one / two:.2f} "
          f"(target >= 1.8); rows identical: {rows1 == rows2}")
    if not args.no_dask:
        from distributed import Client, LocalCluster

        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                          dashboard_address=None) as cluster, Client(cluster) as client:
            dask_s, rows_dask = _timed(client=client)
        figures.update({"wall_s_dask_2_workers": dask_s,
                        "rows_identical_dask": rows_dask == rows1})
        print(f"Dask LocalCluster (2 workers): {dask_s:.2f} s; rows identical: "
              f"{rows_dask == rows1}")
    path = write("sweep", figures=figures, references={"wall_s_1_worker": one},
                 ratios={"speedup_2_workers": one / two})
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
