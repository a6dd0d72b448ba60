"""cProfile of the in-process paths behind the bench targets: where each one's time goes.

    .venv/bin/python bench/profiles.py [core|pvt|trio|trio_compile|parse|wire|session|fanout ...]

For each workload (all by default) prints the share of profiled time by module (self time,
summed per file) and the functions with the most self time. The shape of a profile holds on a
loaded machine even when its absolute figures do not; bench/README.md's "Profiles" section
reads these. ``wire`` and ``fanout`` run the server in this process (the profiler follows its
thread) with the clients in a child process, as the benches do.
"""

from __future__ import annotations

import asyncio
import cProfile
import functools
import pstats
import re
import sys
from collections import defaultdict
from collections.abc import Callable
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))


def _core() -> None:
    from bench.bench_pmac_stream import stream

    stream(50_000)


def _pvt() -> None:
    from bench.bench_pmac_stream import stream

    stream(50_000, mode="pvt")


def _trio() -> None:
    from bench.bench_trio import trio_rate

    trio_rate(20_000)


def _trio_compile() -> None:
    """Issue 32's compile benches: the 1 000-line program with 20 INCLUDEs and the one calling
    a 20-function library, each stored once into a fresh controller."""
    from motionsim.sim.trio import TrioController

    from bench import bench_trio_include as inc
    from bench import bench_trio_library as lib

    c = TrioController("bench", {"model": "mc4xx"})
    for k in range(inc.N_INCLUDES):
        c.store_program(f"INIT{k:02d}", inc.included(k))
    c.store_program("MAIN", inc.main_program())
    c = TrioController("bench", {"model": "mc6xx"})
    c.store_program("MACHINE", lib.library())
    c.store_program("MAIN", lib.main_program())


@functools.cache
def _parse_lines() -> tuple[str, ...]:
    """The bench's corpus, made once (the warm-up call), outside the profile."""
    from bench.bench_parse import corpus

    return tuple(corpus(50_000))


def _parse() -> None:
    from motionsim.sim.pmac.buffers.program import compile_line

    for text in _parse_lines():
        compile_line(text)


def _wire() -> None:
    import multiprocessing as mp

    from motionsim.api.pmac_ethernet.server import serve_pmac

    from bench.bench_wire import _client_process, _controller

    async def main() -> None:
        handle, _ = _controller()
        await handle.command("I3=2 I6=1")
        server = await serve_pmac(handle, "127.0.0.1", 0)
        q = mp.get_context("spawn").Queue()
        proc = mp.get_context("spawn").Process(
            target=_client_process,
            args=(server.sockets[0].getsockname()[1], 1, 3.0, "I16", q))
        proc.start()
        while proc.is_alive() and q.empty():
            await asyncio.sleep(0.05)
        proc.join()
        server.close()

    try:
        import uvloop  # the loop the service runs on, as bench_wire uses

        uvloop.run(main())
    except ImportError:
        asyncio.run(main())


def _session() -> None:
    """3 000 GETRESPONSE "I16" through a PMAC Ethernet session with no socket (what the
    server does per round trip between reading the request and writing the reply; ``wire``
    profiles it with the sockets, mostly waiting)."""
    from motionsim.api.pmac_ethernet.protocol import getresponse
    from motionsim.api.pmac_ethernet.server import PmacSession

    from bench.bench_wire import _controller

    async def main() -> None:
        handle, _ = _controller()
        await handle.command("I3=2 I6=1")
        session = PmacSession(handle, "tcp:profile")
        packet = getresponse("I16")
        for _ in range(3000):
            session.receive(packet)
            async for _out in session.replies():
                pass

    asyncio.run(main())


def _fanout(profile: cProfile.Profile) -> None:
    import motionsim.app.embedded as embedded
    from motionsim.app.kinds import register_kind

    from bench import bench_spine

    register_kind(bench_spine.BenchEmitter)
    real_run = asyncio.run

    class _Profiled:  # the service thread's asyncio.run, under the profiler
        def __getattr__(self, name: str) -> object:
            return getattr(asyncio, name)

        @staticmethod
        def run(coro):  # noqa: ANN001, ANN205 - asyncio.run's own signature
            profile.enable()
            try:
                return real_run(coro)
            finally:
                profile.disable()

    embedded.asyncio = _Profiled()  # type: ignore[assignment]
    try:
        real_run(bench_spine.bench_fanout(100, 250.0, 4.0))
    finally:
        embedded.asyncio = asyncio  # type: ignore[assignment]


WORKLOADS: dict[str, Callable[..., None]] = {
    "core": _core, "pvt": _pvt, "trio": _trio, "trio_compile": _trio_compile, "parse": _parse,
    "wire": _wire, "session": _session, "fanout": _fanout}


def _short(path: str) -> str:
    """A file's path from its package root (the standard library's from ``lib/python3.x``)."""
    for marker in ("site-packages/", str(ROOT) + "/"):
        if marker in path:
            return path.split(marker, 1)[1]
    return re.sub(r"^.*/lib/python3\.\d+/", "", path)


def report(stats: pstats.Stats, top: int = 12) -> str:
    """Self time by module, then the ``top`` functions by self time."""
    raw = stats.stats  # type: ignore[attr-defined]
    total = sum(v[2] for v in raw.values()) or 1.0
    by_module: dict[str, float] = defaultdict(float)
    for (path, _, _), (_, _, tottime, _, _) in raw.items():
        by_module[_short(path)] += tottime
    lines = ["  self time by module:"]
    for module, t in sorted(by_module.items(), key=lambda kv: -kv[1])[:top]:
        lines.append(f"    {100 * t / total:5.1f} %  {module}")
    lines.append("  functions by self time (calls, self %, cumulative %):")
    for (path, line, name), (_, calls, tottime, cumtime, _) in sorted(
            raw.items(), key=lambda kv: -kv[1][2])[:top]:
        lines.append(f"    {calls:>8} {100 * tottime / total:5.1f} % {100 * cumtime / total:6.1f} %"
                     f"  {_short(path)}:{line} {name}")
    return "\n".join(lines)


def main() -> None:
    names = sys.argv[1:] or list(WORKLOADS)
    for name in names:
        profile = cProfile.Profile()
        if name == "fanout":
            _fanout(profile)
        else:
            WORKLOADS[name]()  # warm: imports, caches
            profile.enable()
            WORKLOADS[name]()
            profile.disable()
        print(f"== {name}")
        print(report(pstats.Stats(profile)))


if __name__ == "__main__":
    main()
