"""GETRESPONSE round trips per second over loopback, 1 and 10 concurrent connections.

The server (``motionsim.api.pmac_ethernet.server.serve_pmac``) runs in this process on a controller
with a virtual clock — the real ``pmac`` kind when it is installed, otherwise a minimal stand-in
that answers at once (the figure then measures the protocol path alone). The clients run in a
separate process (asyncio, one task per connection, each sending ``GETRESPONSE "I16"`` and
reading the reply before the next), as a host would. The reference, measured in the same run
with the same clients, is a bare asyncio server reading the same framing and answering a fixed
reply. Prints the figures and writes ``bench/results/wire.json``.

    .venv/bin/python bench/bench_wire.py [--seconds 3] [--command I16]
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

from bench.results import write  # noqa: E402


def _client_process(port: int, connections: int, seconds: float, command: str, q) -> None:
    from motionsim.api.pmac_ethernet.protocol import getresponse

    packet = getresponse(command)

    async def one(stop_at: float, lat: list[float]) -> int:
        reader, writer = await asyncio.open_connection("127.0.0.1", port)
        n = 0
        while time.perf_counter() < stop_at:
            t0 = time.perf_counter()
            writer.write(packet)
            data = await reader.read(4096)
            if not data:
                break
            while data[-1:] not in (b"\x06", b"\r"):
                data += await reader.read(4096)
            lat.append(time.perf_counter() - t0)
            n += 1
        writer.close()
        return n

    async def main() -> tuple[int, float, list[float]]:
        lat: list[float] = []
        start = time.perf_counter()
        counts = await asyncio.gather(*(one(start + seconds, lat) for _ in range(connections)))
        return sum(counts), time.perf_counter() - start, lat

    total, elapsed, lat = asyncio.run(main())
    lat.sort()
    q.put({
        "round_trips": total,
        "seconds": elapsed,
        "per_s": total / elapsed,
        "latency_p50_us": lat[len(lat) // 2] * 1e6 if lat else None,
        "latency_p99_us": lat[int(len(lat) * 0.99)] * 1e6 if lat else None,
    })


def _controller():
    from motionsim.app.kinds import kinds, register_kind
    from motionsim.app.registry import Registry
    from motionsim.sim.controller import Controller, Reply

    registry = Registry()
    if "pmac" in kinds():
        try:
            return registry.add("pmac", "pmac", clock="virtual"), "pmac"
        except Exception as exc:  # noqa: BLE001 - fall back to the stand-in
            print(f"pmac kind unusable ({exc}); using the stand-in", file=sys.stderr)

    class Echo(Controller):
        kind = "bench_echo"

        def terminal(self, command, port=None):
            reply = Reply(command)
            reply.resolve("5", None, self.env.now)
            return reply

        def get_variable(self, name):
            return {"I3": 2, "I6": 1}.get(name.upper(), 0)

    register_kind(Echo)
    return registry.add("bench_echo", "pmac", clock="virtual"), "stand-in (answers at once)"


async def _bare_echo(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
    """The reference: the PMAC Ethernet framing (8-byte header, big-endian length in bytes
    6-7, payload) read exactly, and a fixed reply in the card's form (data, CR, ACK)."""
    try:
        while True:
            header = await reader.readexactly(8)
            await reader.readexactly(int.from_bytes(header[6:8], "big"))
            writer.write(b"5\r\x06")
    except (asyncio.IncompleteReadError, ConnectionError):
        pass
    finally:
        writer.close()


async def _measure(port: int, args, label: str) -> dict:
    ctx = mp.get_context("spawn")
    results = {}
    for connections in (1, 10):
        q = ctx.Queue()
        proc = ctx.Process(target=_client_process,
                           args=(port, connections, args.seconds, args.command, q))
        proc.start()
        while proc.is_alive() and q.empty():
            await asyncio.sleep(0.05)
        res = q.get(timeout=30)
        proc.join()
        results[f"connections_{connections}"] = res
        print(f"{label:<10}{connections:>2} connection(s): {res['per_s']:>9.0f} round trips/s "
              f"(p50 {res['latency_p50_us']:.0f} µs, p99 {res['latency_p99_us']:.0f} µs)")
    return results


async def _serve_and_measure(args) -> dict:
    from motionsim.api.pmac_ethernet.server import serve_pmac

    handle, kind = _controller()
    with __import__("contextlib").suppress(Exception):
        await handle.command("I3=2 I6=1")
    bare = await asyncio.start_server(_bare_echo, "127.0.0.1", 0)
    server = await serve_pmac(handle, "127.0.0.1", 0)
    results = {"controller": kind, "command": args.command}
    reference = {}
    for _ in range(max(1, args.repeat)):  # interleaved, best of each: the machine is shared
        for label, srv, into in (("bare echo", bare, reference), ("motionsim", server, results)):
            got = await _measure(srv.sockets[0].getsockname()[1], args, label)
            for key, res in got.items():
                if key not in into or res["per_s"] > into[key]["per_s"]:
                    into[key] = res
    for srv in (server, bare):
        srv.close()
        await srv.wait_closed()
    results["reference"] = reference
    results["sim_t_after_s"] = handle.controller.now
    return results


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seconds", type=float, default=3.0)
    parser.add_argument("--command", default="I16")
    parser.add_argument("--repeat", type=int, default=2)
    args = parser.parse_args()
    try:
        import uvloop  # same loop uvicorn runs the service on

        uvloop.install()
        loop_name = "uvloop"
    except ImportError:
        loop_name = "asyncio"
    print(f"bench_wire: server loop {loop_name}, clients in a separate process, "
          f"{args.seconds:g} s per run")
    results = asyncio.run(_serve_and_measure(args))
    reference = results.pop("reference")
    ratios = {"getresponse": results["connections_1"]["per_s"]
              / reference["connections_1"]["per_s"],
              "getresponse_10_connections": results["connections_10"]["per_s"]
              / reference["connections_10"]["per_s"]}
    print(f"ratio     : {ratios['getresponse']:.3f} of the bare echo server, 1 connection "
          f"(target >= 0.7); {ratios['getresponse_10_connections']:.3f} with 10")
    path = write("wire", figures={**results, "loop": loop_name},
                 references={"bare_echo": reference}, ratios=ratios)
    print(f"wrote {path.relative_to(ROOT)}")

if __name__ == "__main__":
    main()
