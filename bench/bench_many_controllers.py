"""One service, 100 controllers streaming at once: aggregate lines/s against one controller
alone, and how evenly the service shares itself between them.

The CI use of the service: a hundred jobs, each with its own PMAC controller (virtual clock) on
one ``motionsim serve``, each streaming its rotary buffer through REST as the REST stream bench
does (``POST .../rotary/lines`` a batch of ``X{i}`` 5 ms moves after a ``TA1 TS0 TM5`` header,
then ``POST .../clock/advance`` the time the batch takes, repeat). All start together (after
every controller was made and its program started) and stream until told to stop; the figures
are taken over a window, after a warm-up, in which every one of them is streaming.

* **aggregate / alone** (target >= 0.8): the lines of the batches the 100 finished in the
  window, per wall second, against the same for one controller alone on the same service
  (measured before and after the 100, the best kept);
* **slowest / fastest** (target >= 0.8: the slowest controller within 20 % of the fastest):
  each controller's own lines per wall second — its batches finished in the window, from the
  first of them to the last (where in a round of requests it happened to be does not enter).

The load generator is this process (asyncio, one connection per controller); the service runs
in its own process (``served.py``) with ``MOTIONSIM_MAX_CONTROLLERS`` raised to fit them.

    .venv/bin/python bench/bench_many_controllers.py [--controllers 100] [--batch 50]
        [--warmup 3] [--window 15]

Writes ``bench/results/many_controllers.json``.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import sys
import time
from pathlib import Path

import httpx

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from bench import served  # noqa: E402
from bench.results import write  # noqa: E402

LINES = [f"X{i % 1000}" for i in range(1000)]
MOVE_S = 0.005  # each line is a 5 ms move (TM5)


async def _make(http: httpx.AsyncClient, cid: str) -> str:
    """A PMAC with a 1 000-word rotary buffer running its header; returns its base path."""
    r = await http.post("/controllers", json={"id": cid, "kind": "pmac",
                                              "clock": {"mode": "virtual"}})
    r.raise_for_status()
    base = f"/controllers/{cid}"
    for path, body in ((f"{base}/terminal", {"command": "&1 DEFINE ROT 1000"}),
                       (f"{base}/coord/1/rotary/lines", {"lines": ["TA1 TS0 TM5"],
                                                         "first_seq": 1}),
                       (f"{base}/coord/1/run", None)):
        (await http.post(path, json=body)).raise_for_status()
    return base


async def _stream(http: httpx.AsyncClient, base: str, batch: int, start: asyncio.Event,
                  stop: asyncio.Event) -> list[float]:
    """Stream batches from ``start`` until ``stop``; returns the wall instant each finished."""
    await start.wait()
    seq, i = 2, 0
    done: list[float] = []
    while not stop.is_set():
        chunk = [LINES[(i + j) % 1000] for j in range(batch)]
        i += batch
        r = await http.post(f"{base}/coord/1/rotary/lines",
                            json={"lines": chunk, "first_seq": seq})
        r.raise_for_status()
        seq += len(chunk)
        r = await http.post(f"{base}/clock/advance", json={"seconds": len(chunk) * MOVE_S})
        r.raise_for_status()
        done.append(time.perf_counter())
    return done


async def _run(url: str, tag: str, n: int, batch: int, warmup_s: float,
               window_s: float) -> dict:
    """``n`` controllers streaming at once; their figures over a window in which all of them
    stream (after ``warmup_s``, for ``window_s``)."""
    limits = httpx.Limits(max_connections=n + 4, max_keepalive_connections=n + 4)
    clients = [httpx.AsyncClient(base_url=url, trust_env=False, timeout=600, limits=limits)
               for _ in range(n)]
    try:
        bases = await asyncio.gather(*(_make(http, f"{tag}{i}")
                                       for i, http in enumerate(clients)))
        start, stop = asyncio.Event(), asyncio.Event()
        tasks = [asyncio.create_task(_stream(http, base, batch, start, stop))
                 for http, base in zip(clients, bases, strict=True)]
        # every connection used just before the start (none idles into the server's
        # keep-alive timeout while the others are made)
        await asyncio.gather(*(http.get("/health") for http in clients))
        start.set()
        await asyncio.sleep(warmup_s)
        w0 = time.perf_counter()
        await asyncio.sleep(window_s)
        w1 = time.perf_counter()
        stop.set()
        finished = await asyncio.gather(*tasks)
        for http, base in zip(clients, bases, strict=True):
            (await http.delete(base)).raise_for_status()
    finally:
        for http in clients:
            await http.aclose()
    inside = [[t for t in done if w0 <= t <= w1] for done in finished]
    # each controller's own rate: its batches finished in the window, from the first to the
    # last of them (where in a round of requests it happened to be does not enter)
    rates = [(len(ts) - 1) * batch / (ts[-1] - ts[0]) if len(ts) > 1 else 0.0
             for ts in inside]
    return {"controllers": n, "batch": batch, "window_s": w1 - w0,
            "batches_in_window": sum(len(ts) for ts in inside),
            "aggregate_lines_per_s": sum(len(ts) for ts in inside) * batch / (w1 - w0),
            "slowest_lines_per_s": min(rates), "fastest_lines_per_s": max(rates),
            "slowest_vs_fastest": min(rates) / max(rates) if max(rates) else 0.0,
            "lines_per_s_by_controller": [round(r, 1) for r in rates]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--controllers", type=int, default=100)
    ap.add_argument("--batch", type=int, default=50)
    ap.add_argument("--warmup", type=float, default=3.0, help="seconds before the window")
    ap.add_argument("--window", type=float, default=15.0, help="seconds measured")
    args = ap.parse_args()
    os.environ["MOTIONSIM_MAX_CONTROLLERS"] = str(max(64, args.controllers + 8))
    with served.motionsim() as url:
        w = (args.batch, args.warmup, args.window)
        alone = [asyncio.run(_run(url, "alone", 1, *w))]
        many = asyncio.run(_run(url, "many", args.controllers, *w))
        alone.append(asyncio.run(_run(url, "again", 1, *w)))
    one = max(alone, key=lambda r: r["aggregate_lines_per_s"])
    ratio = many["aggregate_lines_per_s"] / one["aggregate_lines_per_s"]
    print(f"one alone   : {one['aggregate_lines_per_s']:>9,.0f} lines/s  "
          f"(batches of {args.batch}, {args.window:g} s window, best of "
          f"{[round(r['aggregate_lines_per_s']) for r in alone]})")
    print(f"{args.controllers} at once : {many['aggregate_lines_per_s']:>9,.0f} lines/s  "
          f"aggregate; per controller {many['slowest_lines_per_s']:,.0f} .. "
          f"{many['fastest_lines_per_s']:,.0f}")
    print(f"ratio       : {ratio:.3f} of one alone (target >= 0.8); slowest / fastest "
          f"{many['slowest_vs_fastest']:.3f} (target >= 0.8)")
    path = write("many_controllers", figures={"many": many, "alone_runs": alone},
                 references={"one_alone_lines_per_s": one["aggregate_lines_per_s"]},
                 ratios={"aggregate_vs_alone": ratio,
                         "slowest_vs_fastest": many["slowest_vs_fastest"]})
    print(f"wrote {path.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
