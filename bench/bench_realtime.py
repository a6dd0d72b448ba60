"""The realtime clock over a long run: cumulative drift, and ``/health`` while it works.

A ``motionsim serve`` subprocess; a PMAC on a realtime clock at factor 10 with PLC 0 enabled
(50 statements every RTI: the card's own processor model busy) runs for 60 wall seconds = 10
simulated minutes. Meanwhile this process polls ``GET /health`` every 20 ms on one connection.
Drift = |simulated time − factor × wall time since the controller was created| at the end
(target ≤ 10 ms, i.e. none accumulated); ``/health`` p99 (target < 50 ms).

Run: ``.venv/bin/python bench/bench_realtime.py [--wall-s 60]``; writes
``bench/results/realtime.json``.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import httpx

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from bench import served  # noqa: E402
from bench.results import p, write  # noqa: E402

FACTOR = 10.0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--wall-s", type=float, default=60.0)
    args = ap.parse_args()
    health: list[float] = []
    with served.motionsim() as url, httpx.Client(base_url=url, trust_env=False) as http:
        t_created = time.monotonic()
        http.post("/controllers", json={"id": "rt", "kind": "pmac",
                                        "clock": {"mode": "realtime", "factor": FACTOR}})
        t_created = (t_created + time.monotonic()) / 2
        http.put("/controllers/rt/plcs/0", json={"text": "\n".join(["P1=P1+1"] * 50)})
        http.post("/controllers/rt/plcs/0/enable")
        end = time.monotonic() + args.wall_s
        while time.monotonic() < end:
            t0 = time.perf_counter()
            http.get("/health").raise_for_status()
            health.append(time.perf_counter() - t0)
            time.sleep(max(0.0, 0.02 - (time.perf_counter() - t0)))
        t0 = time.monotonic()
        t_sim = http.get("/controllers/rt/clock").json()["t"]
        t1 = time.monotonic()
        wall = (t0 + t1) / 2 - t_created  # the clock was read somewhere in [t0, t1]
        bound = FACTOR * (t1 - t0) / 2
        scans = http.get("/controllers/rt/variables/P1").json()["value"]
    drift = abs(t_sim - FACTOR * wall)
    h99 = p(health, 0.99) * 1e3
    print(f"realtime x{FACTOR:g}: {t_sim:.2f} s simulated in {wall:.2f} s wall: drift "
          f"{drift * 1e3:.1f} ms ± {bound * 1e3:.1f} ms (the clock read's round trip; "
          f"target <= 10 ms); "
          f"PLC 0 scans {scans:,.0f}")
    print(f"/health: {len(health)} polls, p50 {p(health, 0.5) * 1e3:.2f} ms, p99 {h99:.2f} ms "
          "(target < 50 ms)")
    path = write("realtime", figures={"simulated_s": t_sim, "wall_s": wall, "plc0_scans": scans,
                                      "drift_uncertainty_s": bound,
                                      "health_p50_ms": p(health, 0.5) * 1e3},
                 references={"factor": FACTOR},
                 ratios={"drift_s_10min": drift, "health_p99_ms_factor10_plc": h99})
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
