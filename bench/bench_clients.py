"""100 concurrent REST clients against one ``motionsim serve``: errors, latency, memory.

Each of ``CLIENTS`` clients (its own keep-alive connection) sends ``ROUNDS`` rounds of the
requests a host test suite makes — read the controller, one PMAC terminal command (the reply
comes from the simulated background cycle), post a rotary batch, read a page of events — all at
once. Reported: requests, errors (transport failures and 5xx; a 409 "buffer full" is an answer),
p50 / p99 latency, and the server's RSS before and after (``/proc/<pid>/status``). The same
number of clients posting the same batches to ``bare_fastapi.py`` (no simulation) is the
same-run reference for the latency ratio.
"""

from __future__ import annotations

import asyncio
import subprocess
import sys
import time
from pathlib import Path

import httpx

sys.path.insert(0, str(Path(__file__).resolve().parent))
from results import p, write  # noqa: E402
from served import BIN, _wait_accepting, bare_fastapi  # noqa: E402

CLIENTS = 100
ROUNDS = 10
BATCH = ["X1 Y1", "X2 Y2", "X3 Y3", "X4 Y4", "X5 Y5"]


def _rss_kb(pid: int) -> int:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1])
    return -1


async def _client(url: str, i: int, lat: list[float], errors: list[str], bare: bool) -> None:
    async with httpx.AsyncClient(base_url=url, timeout=60, trust_env=False) as http:
        for _ in range(ROUNDS):
            calls = ([("POST", "/controllers/pmac/coord/1/rotary/lines", {"lines": BATCH})]
                     if bare else [
                         ("GET", "/controllers/pmac", None),
                         ("POST", "/controllers/pmac/terminal", {"command": "I16"}),
                         ("POST", "/controllers/pmac/coord/1/rotary/lines", {"lines": BATCH}),
                         ("GET", "/controllers/pmac/events", None)])
            for method, path, body in calls:
                t0 = time.perf_counter()
                try:
                    r = await http.request(method, path, json=body,
                                           params={"limit": 50} if method == "GET" else None)
                    if r.status_code >= 500:
                        errors.append(f"{path}: {r.status_code}")
                except httpx.HTTPError as exc:
                    errors.append(f"{path}: {type(exc).__name__}")
                lat.append(time.perf_counter() - t0)


async def _load(url: str, bare: bool) -> tuple[list[float], list[str], float]:
    lat: list[float] = []
    errors: list[str] = []
    t0 = time.perf_counter()
    await asyncio.gather(*[_client(url, i, lat, errors, bare) for i in range(CLIENTS)])
    return lat, errors, time.perf_counter() - t0


def _serve() -> tuple[subprocess.Popen, str]:
    proc = subprocess.Popen([str(BIN / "motionsim"), "serve", "--port", "0", "--clock",
                             "virtual", "--pmac-port", "0", "--trio-port", "0"],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    for _ in range(200):
        line = proc.stdout.readline()
        if "listening http://" in line:
            url = line.split("listening ", 1)[1].split()[0]
            _wait_accepting(url, time.monotonic() + 30)
            return proc, url
    proc.kill()
    raise RuntimeError("motionsim serve did not start")


def main() -> None:
    proc, url = _serve()
    try:
        httpx.put(url + "/controllers/pmac/coord/1/rotary", json={"size_words": 60000},
                  timeout=30, trust_env=False).raise_for_status()
        rss_before = _rss_kb(proc.pid)
        lat, errors, wall = asyncio.run(_load(url, bare=False))
        rss_after = _rss_kb(proc.pid)
        alive = proc.poll() is None
    finally:
        proc.terminate()
        proc.wait(10)
    with bare_fastapi() as bare_url:
        bare_lat, bare_errors, _ = asyncio.run(_load(bare_url, bare=True))
    figures = {
        "clients": CLIENTS, "requests": len(lat), "errors": len(errors),
        "error_samples": errors[:5], "p50_ms": p(lat, 0.5) * 1e3, "p99_ms": p(lat, 0.99) * 1e3,
        "requests_per_s": len(lat) / wall, "rss_before_mb": rss_before / 1024,
        "rss_after_mb": rss_after / 1024, "service_alive": alive,
    }
    references = {"bare_fastapi_p50_ms": p(bare_lat, 0.5) * 1e3,
                  "bare_fastapi_p99_ms": p(bare_lat, 0.99) * 1e3,
                  "bare_fastapi_errors": len(bare_errors)}
    ratios = {"p99_vs_bare": figures["p99_ms"] / references["bare_fastapi_p99_ms"]}
    write("clients", figures=figures, references=references, ratios=ratios)
    print(f"{CLIENTS} concurrent clients, {len(lat)} requests in {wall:.1f} s: "
          f"{len(errors)} errors, p50 {figures['p50_ms']:.1f} ms, p99 {figures['p99_ms']:.1f} ms "
          f"(bare FastAPI p99 {references['bare_fastapi_p99_ms']:.1f} ms); RSS "
          f"{figures['rss_before_mb']:.1f} -> {figures['rss_after_mb']:.1f} MB; "
          f"service alive: {alive}")


if __name__ == "__main__":
    main()
