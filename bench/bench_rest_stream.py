"""The PMAC rotary stream driven entirely through REST, against the bare SimPy loop and a bare
FastAPI app.

1. **Batches of 500**: 100 000 one-word 5 ms moves (``X{i}`` after a ``TA1 TS0 TM5`` header)
   into a 1 000-word rotary buffer of a ``motionsim serve`` subprocess (virtual clock): POST 500
   lines, ``advance`` the 2.5 s they take, repeat. Lines per wall second against
   :func:`bench.reference_loop.reference_rate` (target ≥ 0.25, issue 35).
2. **One line per request, one connection**: p99 of ``POST .../rotary/lines`` with one line
   against the same POST on ``bench/bare_fastapi.py`` (target ≤ 2x): three rounds of each,
   alternately, both servers up throughout; the best round's p99 of each (a p99 of 1 800
   requests is decided by a few of them, so by whatever else the machine did meanwhile).

The client (this process) is the load generator; the servers run in their own processes.
Run: ``.venv/bin/python bench/bench_rest_stream.py [lines] [one_line_posts]``; writes
``bench/results/rest_stream.json``.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import httpx

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from bench import served  # noqa: E402
from bench.reference_loop import reference_rate  # noqa: E402
from bench.results import p, write  # noqa: E402

LINES = [f"X{i % 1000}" for i in range(1000)]
#: One-line rounds, motionsim and bare FastAPI alternately; each side's best p99 is kept.
ROUNDS = 3


def _controller(http: httpx.Client, cid: str, words: int) -> str:
    http.post("/controllers", json={"id": cid, "kind": "pmac", "clock": {"mode": "virtual"}})
    base = f"/controllers/{cid}"
    http.post(f"{base}/terminal", json={"command": f"&1 DEFINE ROT {words}"})
    http.post(f"{base}/coord/1/rotary/lines", json={"lines": ["TA1 TS0 TM5"], "first_seq": 1})
    http.post(f"{base}/coord/1/run")
    return base


def batches(url: str, n: int, batch: int = 500) -> dict:
    with httpx.Client(base_url=url, trust_env=False, timeout=60) as http:
        base = _controller(http, "rest500", 1000)
        seq = 2
        t0 = time.perf_counter()
        for start in range(0, n, batch):
            chunk = [LINES[i % 1000] for i in range(start, min(n, start + batch))]
            r = http.post(f"{base}/coord/1/rotary/lines", json={"lines": chunk, "first_seq": seq})
            r.raise_for_status()
            seq += len(chunk)
            http.post(f"{base}/clock/advance", json={"seconds": len(chunk) * 0.005})
        wall = time.perf_counter() - t0
        executed = len(http.get(f"{base}/events", params={"type": "move_end", "limit": 1,
                                                           "since": 0}).json()["events"])
        status = http.get(f"{base}/coord/1").json()
    return {"lines": n, "wall_s": wall, "lines_per_s": n / wall, "batch": batch,
            "program": status["program"], "any_move_end": bool(executed)}


def one_line_latencies(url: str, path: str, posts: int, advance: str | None) -> list[float]:
    out = []
    with httpx.Client(base_url=url, trust_env=False, timeout=60) as http:
        for i in range(posts):
            body = {"lines": [LINES[i % 1000]]}
            t0 = time.perf_counter()
            http.post(path, json=body).raise_for_status()
            out.append(time.perf_counter() - t0)
            if advance and i % 100 == 99:
                http.post(advance, json={"seconds": 0.5})
    return out[posts // 10:]  # the first tenth warms the connection and the server up


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 100_000
    posts = int(sys.argv[2]) if len(sys.argv) > 2 else 2_000
    ref = reference_rate(min(n, 200_000))
    with served.motionsim() as url, served.bare_fastapi() as bare_url:
        stream = batches(url, n)
        with httpx.Client(base_url=url, trust_env=False) as http:
            base = _controller(http, "rest1", 65536)
        rounds: list[tuple[list[float], list[float]]] = []
        for _ in range(ROUNDS):  # interleaved, best p99 of each: the machine is shared
            rounds.append((
                one_line_latencies(url, f"{base}/coord/1/rotary/lines", posts,
                                   f"{base}/clock/advance"),
                one_line_latencies(bare_url, "/controllers/x/coord/1/rotary/lines", posts,
                                   None)))
    ours = min((r[0] for r in rounds), key=lambda lat: p(lat, 0.99))
    bare = min((r[1] for r in rounds), key=lambda lat: p(lat, 0.99))
    ratio = stream["lines_per_s"] / ref
    p99, bare_p99 = p(ours, 0.99), p(bare, 0.99)
    print(f"REST stream : {stream['lines_per_s']:>10,.0f} lines/s  ({n:,} lines in batches of "
          f"500, {stream['wall_s']:.1f} s wall)")
    print(f"bare loop   : {ref:>10,.0f} lines/s   ratio {ratio:.3f} (target >= 0.25)")
    print(f"1-line POST : p50 {p(ours, 0.5) * 1e3:.2f} ms, p99 {p99 * 1e3:.2f} ms; bare FastAPI "
          f"p50 {p(bare, 0.5) * 1e3:.2f} ms, p99 {bare_p99 * 1e3:.2f} ms; "
          f"ratio {p99 / bare_p99:.2f} (target <= 2)")
    path = write(
        "rest_stream",
        figures={"stream": stream, "one_line_p50_s": p(ours, 0.5), "one_line_p99_s": p99},
        references={"bare_simpy_lines_per_s": ref, "bare_fastapi_p50_s": p(bare, 0.5),
                    "bare_fastapi_p99_s": bare_p99},
        ratios={"batches_500": ratio, "one_line_p99": p99 / bare_p99},
    )
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
