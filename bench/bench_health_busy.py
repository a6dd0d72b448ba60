"""``/health`` while another client advances a busy controller: no request freezes the service.

A ``motionsim serve`` subprocess (virtual clock). A PMAC with PLC 1 scanning every background
cycle (I5 = 3) and a rotary program of 5 ms moves is advanced by 60 simulated seconds in one
``POST .../clock/advance`` from a second thread, while this thread polls ``GET /health`` every
10 ms on its own connection. Figures: ``/health`` p50 / p99 / max while the advance runs, the
advance's wall time, and the same ``/health`` figures with the server idle (the reference,
same run). Before simulation ran in slices, every request waited for the whole advance.

Run: ``.venv/bin/python bench/bench_health_busy.py [--sim-s 60]``; writes
``bench/results/health_busy.json``.
"""

from __future__ import annotations

import argparse
import sys
import threading
import time
from pathlib import Path

import httpx

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from bench import served  # noqa: E402
from bench.results import p, write  # noqa: E402

PLC = "P1=P1+1\nP2=P1*2\nIF (P2>100)\nP3=P3+1\nENDIF"
POLL_S = 0.01


def poll_health(http: httpx.Client, until: threading.Event | float) -> list[float]:
    """``/health`` round trips (ms) every ``POLL_S`` until the event is set / the instant."""
    out: list[float] = []
    while not (until.is_set() if isinstance(until, threading.Event) else time.monotonic() > until):
        t0 = time.perf_counter()
        assert http.get("/health").status_code == 200
        out.append((time.perf_counter() - t0) * 1000)
        time.sleep(POLL_S)
    return out


def summary(ms: list[float]) -> dict[str, float]:
    return {"n": len(ms), "p50_ms": p(ms, 0.5), "p99_ms": p(ms, 0.99), "max_ms": max(ms)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sim-s", type=float, default=60.0)
    args = ap.parse_args()
    with served.motionsim() as url, \
            httpx.Client(base_url=url, trust_env=False, timeout=600) as busy, \
            httpx.Client(base_url=url, trust_env=False, timeout=30) as http:
        busy.post("/controllers", json={"id": "busy", "kind": "pmac",
                                        "clock": {"mode": "virtual"}})
        busy.put("/controllers/busy/variables/I5", json={"value": 3})
        busy.put("/controllers/busy/plcs/1", json={"text": PLC})
        busy.post("/controllers/busy/plcs/1/enable")
        busy.put("/controllers/busy/coord/1/rotary", json={"size_words": 600})
        busy.post("/controllers/busy/coord/1/rotary/lines",
                  json={"lines": [f"TM5 TA1 TS0 X{i}" for i in range(100)]})
        busy.post("/controllers/busy/coord/1/run")
        idle = poll_health(http, time.monotonic() + 3.0)
        done = threading.Event()
        wall: list[float] = []

        def advance() -> None:
            t0 = time.monotonic()
            r = busy.post("/controllers/busy/clock/advance", json={"seconds": args.sim_s})
            r.raise_for_status()
            wall.append(time.monotonic() - t0)
            done.set()

        worker = threading.Thread(target=advance)
        worker.start()
        during = poll_health(http, done)
        worker.join()
        scans = busy.get("/controllers/busy/plcs").json()["plcs"][0]["scans"]
    figures = {"during_advance": summary(during), "advance_wall_s": wall[0],
               "simulated_s": args.sim_s, "plc1_scans": scans}
    references = {"idle": summary(idle)}
    ratios = {"health_p99_busy_ms": figures["during_advance"]["p99_ms"],
              "health_p99_busy_vs_idle": figures["during_advance"]["p99_ms"]
              / references["idle"]["p99_ms"]}
    path = write("health_busy", figures=figures, references=references, ratios=ratios)
    d, i = figures["during_advance"], references["idle"]
    print(f"advance {args.sim_s:g} simulated s of a busy PMAC (PLC 1, {scans} scans): "
          f"{wall[0]:.2f} wall s")
    print(f"/health during it: n={d['n']} p50 {d['p50_ms']:.1f} ms, p99 {d['p99_ms']:.1f} ms, "
          f"max {d['max_ms']:.1f} ms")
    print(f"/health idle:      n={i['n']} p50 {i['p50_ms']:.1f} ms, p99 {i['p99_ms']:.1f} ms, "
          f"max {i['max_ms']:.1f} ms")
    print(f"-> {path}")


if __name__ == "__main__":
    main()
