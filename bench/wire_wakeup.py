"""What a GETRESPONSE round trip costs when the server needs CPU time: the bare echo of
``bench_wire.py`` made to spin ``busy`` µs before it answers, 1 connection, the same client.

The reference answers in a few µs, before the client's thread has gone to sleep waiting for the
reply; a server that takes longer also pays for waking it (the server's ``write`` p50 shows it).
This bounds the ratio any simulated controller can reach (bench/README.md, "Profiles").

    .venv/bin/python bench/wire_wakeup.py [--seconds 1.5] [--busy 0 10 20 40 80]
"""

from __future__ import annotations

import argparse
import asyncio
import multiprocessing as mp
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from bench.bench_wire import _client_process  # noqa: E402


def _busy_echo(busy_us: float, writes: list[float]):
    async def echo(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        try:
            while True:
                header = await reader.readexactly(8)
                await reader.readexactly(int.from_bytes(header[6:8], "big"))
                end = time.perf_counter() + busy_us * 1e-6
                while time.perf_counter() < end:
                    pass
                t0 = time.perf_counter()
                writer.write(b"5\r\x06")
                writes.append(time.perf_counter() - t0)
        except (asyncio.IncompleteReadError, ConnectionError):
            pass
        finally:
            writer.close()

    return echo


async def _run(args) -> None:
    ctx = mp.get_context("spawn")
    for busy in args.busy:
        writes: list[float] = []
        server = await asyncio.start_server(_busy_echo(busy, writes), "127.0.0.1", 0)
        q = ctx.Queue()
        proc = ctx.Process(target=_client_process, args=(
            server.sockets[0].getsockname()[1], 1, args.seconds, "I16", q))
        proc.start()
        while proc.is_alive() and q.empty():
            await asyncio.sleep(0.05)
        res = q.get(timeout=30)
        proc.join()
        server.close()
        await server.wait_closed()
        writes.sort()
        p50 = writes[len(writes) // 2] * 1e6 if writes else float("nan")
        print(f"busy {busy:>5g} µs: {res['per_s']:>8.0f} round trips/s, "
              f"p50 {res['latency_p50_us']:.0f} µs, server write() p50 {p50:.1f} µs")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=1.5)
    ap.add_argument("--busy", type=float, nargs="+", default=[0, 10, 20, 40, 80])
    args = ap.parse_args()
    try:
        import uvloop

        uvloop.install()
    except ImportError:
        pass
    asyncio.run(_run(args))


if __name__ == "__main__":
    main()
