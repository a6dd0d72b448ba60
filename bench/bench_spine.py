"""Spine bench: event log + bus throughput, WebSocket fan-out latency, realtime lateness.

    .venv/bin/python bench/bench_spine.py [--quick]

Prints the figures and writes ``bench/results/spine.json``:

- ``log``: events/s appended by ``EventLog.emit`` alone, and with 10 bus subscribers
  (``motionsim.app.bus.Cursor``, what each WebSocket subscriber is) each reading every event from
  the ring and encoding it to JSON;
- ``ws_fanout``: a served motionsim (real uvicorn on 127.0.0.1, realtime clock) whose
  controller emits ``rate`` events per second; 100 WebSocket subscribers; latency = wall time
  at receipt − wall time at emission, p50 / p99, and how many messages arrived;
- ``rest``: sequential REST round trips (one keep-alive connection), p50 / p99;
- ``ws_fanout_batch``: the same at 1000 events/s with ``batch=true`` (arrays per message);
- ``realtime``: lateness of the realtime clock's wake-ups (wall time between an event's due
  instant and its processing), p50 / p99, idle and while the fan-out runs.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import simpy  # noqa: E402
from motionsim.app.bus import Cursor  # noqa: E402
from motionsim.app.kinds import register_kind  # noqa: E402
from motionsim.app.settings import Settings  # noqa: E402
from motionsim.sim.controller import Controller, Reply  # noqa: E402
from motionsim.sim.events import EventLog  # noqa: E402


class BenchEmitter(Controller):
    """Emits ``tick`` events every ``period_s``; each carries the wall time it was emitted."""

    kind = "bench_emitter"
    event_types = ("tick",)

    def __init__(self, id, config=None, *, log_capacity=100_000):
        super().__init__(id, config, log_capacity=log_capacity)
        self.period_s = float(self.config.get("period_s", 0.001))
        self.env.process(self._tick())

    def _tick(self):
        k = 0
        while True:
            k += 1
            yield self.env.timeout(k * self.period_s - self.env.now)
            self.log.emit("tick", k=k, wall=time.time())

    def terminal(self, command, port=None):
        reply = Reply(command)
        reply.resolve(command, None, self.env.now)
        return reply

    def reset(self):
        pass


def pct(values: list[float], q: float) -> float:
    if not values:
        return float("nan")
    values = sorted(values)
    return values[min(len(values) - 1, int(q * len(values)))]


def bench_log(n: int) -> dict:
    env = simpy.Environment()
    log = EventLog(env, "b", capacity=100_000)
    t0 = time.perf_counter()
    for i in range(n):
        log.emit("tick", k=i)
    emit_rate = n / (time.perf_counter() - t0)

    env = simpy.Environment()
    log = EventLog(env, "b", capacity=100_000)
    cursors = [Cursor(log, batch=256) for _ in range(10)]
    t0 = time.perf_counter()
    chunk = 1000
    for start in range(0, n, chunk):
        for i in range(start, start + chunk):
            log.emit("tick", k=i)
        for cursor in cursors:
            while cursor.behind:
                for message in cursor.read():
                    json.dumps(message)
    bus_rate = n / (time.perf_counter() - t0)
    return {"events": n, "emit_per_s": round(emit_rate), "emit_plus_10_readers_per_s":
            round(bus_rate)}


class _Subscriber(asyncio.Protocol):
    """One WebSocket subscriber, as cheap as a reader can be: a handshake, then the server's
    frames (unmasked: RFC 6455 5.1) cut by hand; text messages timed, pings answered.

    The ``websockets`` client costs ~20 us of Python per message (more with a
    ``wait_for`` per ``recv``, a task each on Python 3.11): 100 subscribers x 250 events/s in
    one process made the load generator, not the server measured, the limit (35 % of the
    messages delivered to the bare broadcaster, p99 seconds of queueing in this process).
    The same subscribers read from both servers."""

    def __init__(self, key: bytes, latencies: list[float], counts: list[int], i: int) -> None:
        self.key, self.latencies, self.counts, self.i = key, latencies, counts, i
        self.buf = bytearray()
        self.opened: asyncio.Future[None] = asyncio.get_running_loop().create_future()
        self.closed: asyncio.Future[None] = asyncio.get_running_loop().create_future()
        self.transport: asyncio.Transport | None = None

    def connection_made(self, transport) -> None:  # noqa: ANN001 - asyncio's signature
        self.transport = transport

    def connection_lost(self, exc) -> None:  # noqa: ANN001
        if not self.closed.done():
            self.closed.set_result(None)

    def data_received(self, data: bytes) -> None:
        buf = self.buf
        buf += data
        at = 0
        if not self.opened.done():
            end = buf.find(b"\r\n\r\n")
            if end < 0:
                return
            if b" 101 " not in buf[:end]:
                self.opened.set_exception(ConnectionError(bytes(buf[:end]).decode()))
                return
            self.opened.set_result(None)
            at = end + 4
        n_buf = len(buf)
        while n_buf - at >= 2:
            op, n, head = buf[at] & 0x0F, buf[at + 1] & 0x7F, 2
            if n == 126:
                if n_buf - at < 4:
                    break
                n, head = int.from_bytes(buf[at + 2:at + 4], "big"), 4
            elif n == 127:
                if n_buf - at < 10:
                    break
                n, head = int.from_bytes(buf[at + 2:at + 10], "big"), 10
            if n_buf - at < head + n:
                break
            payload = bytes(buf[at + head:at + head + n])
            at += head + n
            if op == 1:
                self._message(payload)
            elif op == 9 and self.transport is not None:  # ping: a masked pong (zero mask)
                self.transport.write(bytes((0x8A, 0x80 | len(payload))) + bytes(4) + payload)
        del buf[:at]

    def _message(self, payload: bytes) -> None:
        now = time.time()
        data = json.loads(payload)
        for ev in data if isinstance(data, list) else (data,):
            if "wall" in ev:
                self.latencies.append(now - ev["wall"])
                self.counts[self.i] += 1


async def _subscriber(url: str, latencies: list[float], counts: list[int], i: int) -> None:
    """Subscribe to ``url`` (``ws://host:port/path?query``) and receive until cancelled."""
    import base64
    import os
    from urllib.parse import urlsplit

    parts = urlsplit(url)
    key = base64.b64encode(os.urandom(16))
    loop = asyncio.get_running_loop()
    transport, proto = await loop.create_connection(
        lambda: _Subscriber(key, latencies, counts, i), parts.hostname, parts.port)
    path = parts.path + ("?" + parts.query if parts.query else "")
    transport.write(f"GET {path} HTTP/1.1\r\nHost: {parts.netloc}\r\nUpgrade: websocket\r\n"
                    f"Connection: Upgrade\r\nSec-WebSocket-Key: {key.decode()}\r\n"
                    "Sec-WebSocket-Version: 13\r\n\r\n".encode())
    try:
        await proto.opened
        await proto.closed
    finally:
        transport.close()


def _rest_round_trips(url: str, n: int) -> list[float]:
    """Sequential ``GET /controllers/b/clock`` round trips on one keep-alive connection."""
    import httpx

    out = []
    with httpx.Client(base_url=url, trust_env=False) as http:
        http.get("/health")
        for _ in range(n):
            t0 = time.perf_counter()
            http.get("/controllers/b/clock").raise_for_status()
            out.append(time.perf_counter() - t0)
    return out


async def _subscribe_all(url: str, subscribers: int, warmup_s: float, seconds: float) -> dict:
    """Connect ``subscribers`` WebSockets, measure for ``seconds`` after ``warmup_s``."""
    latencies: list[float] = []
    counts = [0] * subscribers
    tasks = [asyncio.create_task(_subscriber(url, latencies, counts, i))
             for i in range(subscribers)]
    await asyncio.sleep(warmup_s)
    latencies.clear()
    counts[:] = [0] * subscribers
    await asyncio.sleep(seconds)
    n = sum(counts)
    window = list(latencies)
    for task in tasks:
        task.cancel()
    await asyncio.gather(*tasks, return_exceptions=True)
    return {"messages": n, "p50": pct(window, 0.5), "p99": pct(window, 0.99)}


async def bench_fanout(subscribers: int, rate: float, seconds: float,
                       batch: bool = False) -> dict:
    """Server in this process (embedded), subscribers in a child process (no shared GIL)."""
    from motionsim.app.embedded import EmbeddedService

    settings = Settings(port=0, pmac_port=0, trio_port=0, controllers=[
        {"id": "b", "kind": "bench_emitter", "clock": {"mode": "realtime", "factor": 1},
         "config": {"period_s": 1.0 / rate}}])
    svc = EmbeddedService(settings).start()
    try:
        handle = svc.app.state.registry.get("b")
        rtt = await asyncio.to_thread(_rest_round_trips, svc.url, 300)
        handle.clock.lateness_s.clear()
        await asyncio.sleep(1.0)
        idle = list(handle.clock.lateness_s)
        url = svc.url.replace("http", "ws") + "/controllers/b/events?type=tick&since=" + str(
            handle.controller.log.last_seq) + ("&batch=true" if batch else "")
        warmup = 2.0
        child = await asyncio.create_subprocess_exec(
            sys.executable, __file__, "--child", url, str(subscribers), str(warmup),
            str(seconds), stdout=asyncio.subprocess.PIPE)
        await asyncio.sleep(warmup + 0.2)
        handle.clock.lateness_s.clear()
        cpu_clock = time.pthread_getcpuclockid(svc._thread.ident)  # the service's thread
        cpu0, seq0 = time.clock_gettime(cpu_clock), handle.controller.log.last_seq
        await asyncio.sleep(seconds - 0.4)
        loaded = list(handle.clock.lateness_s)
        cpu_s = time.clock_gettime(cpu_clock) - cpu0
        events = handle.controller.log.last_seq - seq0
        stdout, _ = await child.communicate()
        res = json.loads(stdout.decode().strip().splitlines()[-1])
    finally:
        svc.stop()
    expected = rate * seconds * subscribers
    return {
        "rest": {"requests": len(rtt), "round_trip_p50_ms": round(pct(rtt, 0.5) * 1e3, 3),
                 "round_trip_p99_ms": round(pct(rtt, 0.99) * 1e3, 3)},
        "ws_fanout": {"subscribers": subscribers, "events_per_s": rate, "seconds": seconds,
                      "batch": batch,
                      "messages": res["messages"], "expected_messages": round(expected),
                      "latency_p50_ms": round(res["p50"] * 1e3, 3),
                      "latency_p99_ms": round(res["p99"] * 1e3, 3),
                      # the service thread's CPU per event per subscriber (all its work:
                      # clock, simulation, fan-out), over the window lateness is taken in
                      "server_cpu_us_per_message": round(
                          cpu_s / max(1, events * subscribers) * 1e6, 2)},
        "realtime": {"idle_lateness_p50_ms": round(pct(idle, 0.5) * 1e3, 3),
                     "idle_lateness_p99_ms": round(pct(idle, 0.99) * 1e3, 3),
                     "loaded_lateness_p50_ms": round(pct(loaded, 0.5) * 1e3, 3),
                     "loaded_lateness_p99_ms": round(pct(loaded, 0.99) * 1e3, 3),
                     "samples_idle": len(idle), "samples_loaded": len(loaded)},
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="smaller run")
    ap.add_argument("--child", nargs=4, metavar=("URL", "N", "WARMUP", "SECONDS"),
                    help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        url, n, warm, secs = args.child
        print(json.dumps(asyncio.run(_subscribe_all(url, int(n), float(warm), float(secs)))))
        return
    register_kind(BenchEmitter)
    n = 200_000 if args.quick else 1_000_000
    out = {"log": bench_log(n)}
    print(f"log: emit {out['log']['emit_per_s']:,} events/s; emit + 10 readers "
          f"{out['log']['emit_plus_10_readers_per_s']:,} events/s")
    fan = asyncio.run(bench_fanout(100, 100.0, 2.0 if args.quick else 5.0))
    out.update(fan)
    f, r, h = fan["ws_fanout"], fan["realtime"], fan["rest"]
    print(f"rest: GET clock round trip p50 {h['round_trip_p50_ms']} ms "
          f"p99 {h['round_trip_p99_ms']} ms")
    print(f"ws fan-out: {f['subscribers']} subscribers x {f['events_per_s']:.0f} events/s: "
          f"{f['messages']}/{f['expected_messages']} messages, latency p50 "
          f"{f['latency_p50_ms']} ms p99 {f['latency_p99_ms']} ms")
    print(f"realtime lateness: idle p50 {r['idle_lateness_p50_ms']} ms p99 "
          f"{r['idle_lateness_p99_ms']} ms; under fan-out p50 {r['loaded_lateness_p50_ms']} ms "
          f"p99 {r['loaded_lateness_p99_ms']} ms")
    fast = asyncio.run(bench_fanout(100, 1000.0, 2.0 if args.quick else 3.0, batch=True))
    out["ws_fanout_batch"] = fast["ws_fanout"]
    b = fast["ws_fanout"]
    print(f"ws fan-out (batch=true): {b['subscribers']} subscribers x {b['events_per_s']:.0f} "
          f"events/s: {b['messages']}/{b['expected_messages']} events, latency p50 "
          f"{b['latency_p50_ms']} ms p99 {b['latency_p99_ms']} ms")
    out["python"] = sys.version.split()[0]
    results = ROOT / "bench" / "results"
    results.mkdir(parents=True, exist_ok=True)
    (results / "spine.json").write_text(json.dumps(out, indent=2) + "\n")
    print(f"wrote {results / 'spine.json'}")


if __name__ == "__main__":
    main()
