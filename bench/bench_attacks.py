"""``/health`` while each attack of issue 23 runs: no request holds the service.

A ``motionsim serve`` subprocess (virtual clock, PMAC and Trio TCP ports on free ports). For
each attack a thread (or a pool) runs it while this thread polls ``GET /health`` every 10 ms
on its own keep-alive connection; the figures are ``/health`` p50 / p99 / max during the
attack, with the attack's own figures (requests, answers, refusals, wall time). The reference
is ``/health`` on the idle server in the same run. Target: p99 under 50 ms during each.

Attacks: a catastrophic fault ``match`` hit over the PMAC port; rotary batches of 1 000 long
lines and one of 200 000 lines (refused); a 300-KB Trio program and a 4 000-line PLC; 1 100
half-sent HTTP requests; leaked sockets filling the PMAC port's cap, then a real host; an
``advance 1e6`` deleted mid-way; a 20-MB body to a 8-MiB limit, sent whole by ``http.client``.

Issue 33's attacks through the program languages and the connection pools: ``P1=`` + 300
``(`` packets on the PMAC port; a PLC issuing 100 ``CMD"..."`` per scan on a realtime card,
then ``DISABLE PLC``; Trio ``DIM a(100000000)`` / ``STRING(2000000000)``; a looping forward
kinematic program and one TCP host repeating ``&1 PMATCH``; a 200 000-character PLC on a
realtime card; 620 idle WebSocket subscribers against an 800-connection cap (then a new REST
client and ``/health``); a Modbus master pipelining FC3 reads without reading the replies while
the PMAC and Trio ports are used.

Run: ``.venv/bin/python bench/bench_attacks.py``; writes ``bench/results/attacks.json``.
"""

from __future__ import annotations

import http.client
import json
import re
import socket
import struct
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import httpx

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from bench.results import p, write  # noqa: E402
from bench.served import BIN  # noqa: E402

POLL_S = 0.01
GETRESPONSE = struct.Struct(">BBHHH")
LONG = "X{i} " + " ".join(f"P{j}=P{j}+{{i}}" for j in range(20))
PLC = "P1=P1+1\nP2=P1*2\nIF (P2>100)\nP3=P3+1\nENDIF"


@contextmanager
def serve(settings: dict[str, Any]) -> Iterator[tuple[str, dict[str, int]]]:
    """``motionsim serve`` with ``settings`` (a config file); its URL and protocol ports."""
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
        json.dump(settings, f)
    argv = [str(BIN / "motionsim"), "serve", "--port", "0", "--clock", "virtual",
            "--pmac-port", "auto", "--trio-port", "auto", "--modbus-port", "auto",
            "--config", f.name]
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    ports: dict[str, int] = {}
    try:
        end = time.monotonic() + 60
        while "http" not in ports and time.monotonic() < end:
            line = proc.stdout.readline()
            if not line:
                raise RuntimeError("motionsim serve did not start")
            m = re.search(r"listening (\w+)://127\.0\.0\.1:(\d+)", line)
            if m:
                ports[m.group(1)] = int(m.group(2))
        threading.Thread(target=proc.stdout.read, daemon=True).start()  # drain its output
        yield f"http://127.0.0.1:{ports['http']}", ports
    finally:
        proc.terminate()
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


def poll_health(http: httpx.Client, done: threading.Event) -> list[float]:
    out: list[float] = []
    while not done.is_set():
        t0 = time.perf_counter()
        assert http.get("/health").status_code == 200
        out.append((time.perf_counter() - t0) * 1000)
        time.sleep(POLL_S)
    return out


def summary(ms: list[float]) -> dict[str, float]:
    return {"n": len(ms), "p50_ms": p(ms, 0.5), "p99_ms": p(ms, 0.99), "max_ms": max(ms)}


def during(http: httpx.Client, attack: Callable[[], dict[str, Any]]) -> dict[str, Any]:
    """Run ``attack`` in a thread while polling ``/health``; both figures."""
    done = threading.Event()
    result: dict[str, Any] = {}

    def run() -> None:
        t0 = time.monotonic()
        try:
            result.update(attack())
        except Exception as exc:  # noqa: BLE001 - reported in the figures
            result["error"] = f"{type(exc).__name__}: {exc}"
        result["wall_s"] = round(time.monotonic() - t0, 3)
        done.set()

    worker = threading.Thread(target=run)
    worker.start()
    polled = poll_health(http, done)
    worker.join()
    return {"health": summary(polled), "attack": result}


def pmac_ask(sock: socket.socket, command: str) -> bytes:
    data = command.encode() + b"\0"
    sock.sendall(GETRESPONSE.pack(0x40, 0xBF, 0, 0, len(data)) + data)
    got = b""
    while not (got.endswith(b"\x06") or (b"\x07" in got and got.endswith(b"\r"))):
        chunk = sock.recv(4096)
        if not chunk:
            raise ConnectionError("closed")
        got += chunk
    return got


# -- the attacks ------------------------------------------------------------------------------

def regex_over_tcp(url: str, ports: dict[str, int]) -> dict[str, Any]:
    httpx.post(f"{url}/controllers/pmac/faults", json={"kind": "error_reply",
                                                      "match": "(a+)+$", "error": "ERR003"})
    answered = 0
    with socket.create_connection(("127.0.0.1", ports["pmac"]), timeout=30) as sock:
        for _ in range(200):
            pmac_ask(sock, "A" * 40 + "!")
            answered += 1
    httpx.delete(f"{url}/controllers/pmac/faults")
    return {"commands": 200, "answered": answered, "pattern": "(a+)+$", "subject_chars": 41}


def big_batches(url: str, ports: dict[str, int]) -> dict[str, Any]:
    with httpx.Client(base_url=url, trust_env=False, timeout=120) as c:
        c.put("/controllers/pmac/coord/1/rotary", json={"size_words": 65536})
        statuses = []
        for k in range(3):
            r = c.post("/controllers/pmac/coord/1/rotary/lines",
                       json={"lines": [LONG.format(i=k * 1000 + i) for i in range(1000)]})
            statuses.append(r.status_code)
            c.delete("/controllers/pmac/coord/1/rotary")
            c.put("/controllers/pmac/coord/1/rotary", json={"size_words": 65536})
        huge = c.post("/controllers/pmac/coord/1/rotary/lines", json={"lines": ["X1"] * 200_000})
        c.delete("/controllers/pmac/coord/1/rotary")
    return {"long_line_batches": statuses, "lines_per_batch": 1000,
            "batch_200000_x1": huge.status_code}


def program_stores(url: str, ports: dict[str, int]) -> dict[str, Any]:
    program = "\n".join(f"VR({i % 500})=VR({i % 500})+{i}*2" for i in range(14000))
    plc = "\n".join(f"P{i % 900}=P{i % 900}+{i}*2+SIN(P{(i + 1) % 900})" for i in range(4000))
    with httpx.Client(base_url=url, trust_env=False, timeout=120) as c:
        trio = c.put("/controllers/trio/programs/BIG", content=program,
                     headers={"content-type": "text/plain"})
        pmac = c.put("/controllers/pmac/plcs/2", json={"text": plc})
    return {"trio_program_bytes": len(program), "trio_status": trio.status_code,
            "plc_bytes": len(plc), "plc_status": pmac.status_code}


def slowloris(url: str, ports: dict[str, int]) -> dict[str, Any]:
    socks, refused = [], 0
    for _ in range(1100):
        try:
            s = socket.create_connection(("127.0.0.1", ports["http"]), timeout=5)
            s.sendall(b"GET /health HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ")
            socks.append(s)
        except OSError:
            refused += 1
    time.sleep(4.0)  # beyond the header time-out set for this run (2 s)
    closed = 0
    for s in socks:
        s.settimeout(0.5)
        try:
            data = s.recv(4096)
            closed += data == b"" or data.startswith(b"HTTP/1.1 408") \
                or data.startswith(b"HTTP/1.1 503")
        except OSError:
            closed += 1
        s.close()
    return {"half_sent": 1100, "refused_at_connect": refused, "answered_408_503_or_closed":
            closed}


def tcp_lockout(url: str, ports: dict[str, int]) -> dict[str, Any]:
    leaked = [socket.create_connection(("127.0.0.1", ports["pmac"]), timeout=5)
              for _ in range(40)]
    t0 = time.monotonic()
    with socket.create_connection(("127.0.0.1", ports["pmac"]), timeout=10) as host:
        reply = pmac_ask(host, "I16")
    served_ms = (time.monotonic() - t0) * 1000
    for s in leaked:
        s.close()
    return {"leaked_sockets": 40, "cap": 32, "host_served": reply.endswith(b"\x06"),
            "host_reply_ms": round(served_ms, 1)}


def delete_mid_advance(url: str, ports: dict[str, int]) -> dict[str, Any]:
    with httpx.Client(base_url=url, trust_env=False, timeout=600) as c:
        c.post("/controllers", json={"id": "busy", "kind": "pmac", "clock": {"mode": "virtual"}})
        c.put("/controllers/busy/variables/I5", json={"value": 3})
        c.put("/controllers/busy/plcs/1", json={"text": PLC})
        c.post("/controllers/busy/plcs/1/enable")
        answer: list[httpx.Response] = []
        t = threading.Thread(target=lambda: answer.append(
            c.post("/controllers/busy/clock/advance", json={"seconds": 1e6})))
        t.start()
        time.sleep(1.0)
        with httpx.Client(base_url=url, trust_env=False, timeout=30) as d:
            t0 = time.monotonic()
            d.delete("/controllers/busy")
        t.join()
        late_ms = (time.monotonic() - t0) * 1000
    return {"advance_status": answer[0].status_code, "answered_after_delete_ms":
            round(late_ms, 1)}


def big_body(url: str, ports: dict[str, int]) -> dict[str, Any]:
    body = b'{"lines": ["' + b"X" * 20_000_000 + b'"]}'
    conn = http.client.HTTPConnection("127.0.0.1", ports["http"], timeout=60)
    try:
        conn.request("POST", "/controllers/pmac/coord/1/rotary/lines", body=body,
                     headers={"content-type": "application/json"})
        r = conn.getresponse()
        status, code = r.status, json.loads(r.read())["code"]
    finally:
        conn.close()
    return {"body_bytes": len(body), "status": status, "code": code}


def deep_nesting_over_tcp(url: str, ports: dict[str, int]) -> dict[str, Any]:
    """Issue 33 item 1: ``P1=`` + 300 ``(`` in one packet killed the realtime card (700 levels
    is the deepest a 1 492-byte packet holds)."""
    replies = []
    with socket.create_connection(("127.0.0.1", ports["pmac"]), timeout=30) as sock:
        for depth in (32, 33, 300, 700):
            replies.append(pmac_ask(sock, "P1=" + "(" * depth + "1" + ")" * depth))
        for _ in range(200):
            pmac_ask(sock, "P1=" + "(" * 300 + "1" + ")" * 300)
        alive = pmac_ask(sock, "P1=7 P1")
    return {"depths": [32, 33, 300, 700], "err003": [b"ERR003" in r for r in replies],
            "card_answers_after": alive.startswith(b"7")}


def _realtime_pmac(c: httpx.Client, cid: str) -> None:
    c.post("/controllers", json={"id": cid, "kind": "pmac", "clock": {"mode": "realtime"}})
    c.post(f"/controllers/{cid}/terminal", json={"command": "I5=3"})


def plc_cmd_flood(url: str, ports: dict[str, int]) -> dict[str, Any]:
    """Issue 33 item 2: 100 CMD"..." per scan grew the command queue without bound."""
    plc = "\n".join(f'CMD"P{100 + k}=P{100 + k}+1"' for k in range(100))
    with httpx.Client(base_url=url, trust_env=False, timeout=30) as c:
        _realtime_pmac(c, "flood")
        c.put("/controllers/flood/plcs/1", json={"text": plc})
        c.post("/controllers/flood/plcs/1/enable")
        time.sleep(5.0)
        t0 = time.monotonic()
        host = c.post("/controllers/flood/terminal", json={"command": "P2=42 P2"}).json()
        host_ms = (time.monotonic() - t0) * 1000
        c.post("/controllers/flood/terminal", json={"command": "DISABLE PLC 1"})
        before = c.post("/controllers/flood/terminal", json={"command": "P100"}).json()["reply"]
        time.sleep(1.0)
        after = c.post("/controllers/flood/terminal", json={"command": "P100"}).json()["reply"]
        c.delete("/controllers/flood")
    return {"cmds_per_scan": 100, "host_reply": host.get("reply"), "host_reply_ms":
            round(host_ms, 1), "commands_run_after_disable": float(after) - float(before)}


def trio_huge_dim(url: str, ports: dict[str, int]) -> dict[str, Any]:
    """Issue 33 item 3: DIM a(100000000) allocated 800 MB on the loop, 400000000 killed it."""
    out = {}
    with httpx.Client(base_url=url, trust_env=False, timeout=30) as c:
        c.post("/controllers", json={"id": "mc4", "kind": "trio", "config": {"model": "mc4xx"},
                                     "clock": {"mode": "virtual"}})
        for text in ("DIM a(100000000) AS INTEGER", "DIM a(400000000) AS INTEGER",
                     "DIM s AS STRING(2000000000)"):
            r = c.put("/controllers/mc4/programs/HUGE", content=text,
                      headers={"content-type": "text/plain"})
            out[text] = r.status_code
        c.delete("/controllers/mc4")
    return out


def kinematic_loop(url: str, ports: dict[str, int]) -> dict[str, Any]:
    """Issue 33 item 4: a looping forward program ran 100 000 statements per PMATCH."""
    setup = ["&1 #1->I #2->I", "&1 OPEN FORWARD CLEAR", "Q7=0", "Q8=0", "WHILE (1>0)",
             "Q40=Q40+1", "ENDWHILE", "CLOSE", "I5150=1"]
    with socket.create_connection(("127.0.0.1", ports["pmac"]), timeout=60) as sock:
        for line in setup:
            pmac_ask(sock, line)
        for _ in range(50):
            pmac_ask(sock, "&1 PMATCH")
        # leave the served card as it was: with I5150=1 its runaway forward program ran its
        # 5 000-statement guard on every later position read, the next attacks' too
        for line in ("I5150=0", "&1 OPEN FORWARD CLEAR", "CLOSE"):
            pmac_ask(sock, line)
    return {"pmatch": 50}


def big_plc_realtime(url: str, ports: dict[str, int]) -> dict[str, Any]:
    """Issue 33 item 4: a PLC at the 200 000-character cap on a realtime card."""
    lines, size = [], 0
    while size < 195_000:
        line = f"P{len(lines) % 900}=P{len(lines) % 900}+1"
        lines.append(line)
        size += len(line) + 1
    with httpx.Client(base_url=url, trust_env=False, timeout=60) as c:
        _realtime_pmac(c, "bigplc")
        status = c.put("/controllers/bigplc/plcs/2", json={"text": "\n".join(lines)}).status_code
        c.post("/controllers/bigplc/plcs/2/enable")
        time.sleep(8.0)
        lag = [e for e in c.get("/controllers/bigplc/events",
                                params={"type": "clock_lag"}).json()["events"]]
        c.delete("/controllers/bigplc")
    return {"plc_chars": size, "status": status, "clock_lag_events": len(lag),
            "reported_behind": any(e.get("behind") for e in lag)}


def websocket_pool(url: str, ports: dict[str, int]) -> dict[str, Any]:
    """Issue 33 item 5: 800 idle WebSocket subscribers made every REST client get 503."""
    upgrade = (b"GET /controllers/pmac/events HTTP/1.1\r\nHost: 127.0.0.1\r\n"
               b"Upgrade: websocket\r\nConnection: Upgrade\r\n"
               b"Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n")
    subs, accepted, refused = [], 0, 0
    for _ in range(800):
        s = socket.create_connection(("127.0.0.1", ports["http"]), timeout=10)
        s.sendall(upgrade)
        head = s.recv(4096)
        if head.startswith(b"HTTP/1.1 101"):
            accepted += 1
            subs.append(s)
        else:
            refused += 1
            s.close()
    with httpx.Client(base_url=url, trust_env=False, timeout=10) as fresh:
        rest = fresh.get("/controllers").status_code
        health = fresh.get("/health").status_code
    for s in subs:
        s.close()
    return {"websockets_tried": 800, "accepted": accepted, "refused": refused,
            "new_rest_client": rest, "new_health_client": health}


def modbus_pipeline(url: str, ports: dict[str, int]) -> dict[str, Any]:
    """Issue 33 item 6: FC3 pipelined without reading made the PMAC / Trio ports time out."""
    fc3 = b"".join(struct.pack(">HHHBBHH", t, 0, 6, 1, 3, 0, 125) for t in range(20_000))
    master = socket.create_connection(("127.0.0.1", ports["modbus"]), timeout=10)
    master.sendall(fc3[:400_000])  # and never reads
    t0 = time.monotonic()
    with socket.create_connection(("127.0.0.1", ports["pmac"]), timeout=10) as pmac:
        reply = pmac_ask(pmac, "I16")
    pmac_ms = (time.monotonic() - t0) * 1000
    t0 = time.monotonic()
    with socket.create_connection(("127.0.0.1", ports["telnet"]), timeout=10) as trio:
        trio.sendall(b"? VR(1)\r\n")
        got = b""
        while b">>" not in got:
            got += trio.recv(4096)
    trio_ms = (time.monotonic() - t0) * 1000
    master.close()
    return {"fc3_sent": 20_000, "pmac_answered": reply.endswith(b"\x06"),
            "pmac_reply_ms": round(pmac_ms, 1), "trio_reply_ms": round(trio_ms, 1)}


ATTACKS: dict[str, Callable[[str, dict[str, int]], dict[str, Any]]] = {
    "regex_over_tcp": regex_over_tcp, "big_batches": big_batches,
    "program_stores": program_stores, "slowloris": slowloris, "tcp_lockout": tcp_lockout,
    "delete_mid_advance": delete_mid_advance, "big_body": big_body,
    "deep_nesting_over_tcp": deep_nesting_over_tcp, "plc_cmd_flood": plc_cmd_flood,
    "trio_huge_dim": trio_huge_dim, "kinematic_loop": kinematic_loop,
    "big_plc_realtime": big_plc_realtime, "websocket_pool": websocket_pool,
    "modbus_pipeline": modbus_pipeline,
}


def main() -> None:
    settings = {"http_header_timeout_s": 2.0, "http_max_connections": 800}
    figures: dict[str, Any] = {}
    with serve(settings) as (url, ports), \
            httpx.Client(base_url=url, trust_env=False, timeout=30) as http_client:
        idle_done = threading.Event()
        threading.Timer(3.0, idle_done.set).start()
        idle = summary(poll_health(http_client, idle_done))
        chosen = sys.argv[1:] or list(ATTACKS)  # `bench_attacks.py NAME...`: only those
        for name in chosen:
            attack = ATTACKS[name]
            figures[name] = during(http_client, lambda a=attack: a(url, ports))
            h = figures[name]["health"]
            print(f"{name:20s} /health p50 {h['p50_ms']:6.1f} ms  p99 {h['p99_ms']:6.1f} ms  "
                  f"max {h['max_ms']:7.1f} ms  n={h['n']:4d}  {figures[name]['attack']}")
    print(f"{'idle':20s} /health p50 {idle['p50_ms']:6.1f} ms  p99 {idle['p99_ms']:6.1f} ms")
    ratios = {f"health_p99_ms_{name}": f["health"]["p99_ms"] for name, f in figures.items()}
    ratios["health_p99_ms_worst_attack"] = max(ratios.values())
    path = write("attacks", figures=figures, references={"idle": idle}, ratios=ratios)
    print(f"-> {path}")


if __name__ == "__main__":
    main()
