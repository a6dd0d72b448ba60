"""Real PMAC host software, unmodified, against a real ``motionsim serve`` subprocess.

* dls-pmaclib's ``PmacEthernetInterface`` (PyPI ``dls-pmaclib``), in a process of its own:
  connect handshake (``i6=1 i3=2 ver`` answered ``^\\d+\\.\\d+\\s*\\r\\x06$``), ``cid``, ``i16``,
  define a rotary buffer, stream lines into it, read ``PR``.
* the EPICS ``pmac`` driver's exchange (pmacAsynIPPort.c), by hand: VR_PMAC_FLUSH (one byte
  back), then VR_PMAC_GETRESPONSE carrying ``cmd\\n`` with up to 40 space-separated queries,
  answered one ``\\r``-terminated line each and one ACK.

The lines streamed over TCP show in the controller's event log through REST, exactly like
lines posted over HTTP (spec pmac.md §5.2, §5.3; issue 6).
"""

from __future__ import annotations

import json
import os
import re
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import httpx
import pytest

from tests.ports import free_port
from tests.processes import stop

ROOT = Path(__file__).resolve().parents[2]
START_TIMEOUT_S = 30.0


class Service:
    """A ``motionsim serve`` subprocess and the ports it printed."""

    def __init__(self, proc: subprocess.Popen, lines: list[str]) -> None:
        self.proc = proc
        self.lines = lines
        self.listening = {m.group(1): int(m.group(2)) for line in lines
                          if (m := re.search(r"listening (\w+)://[\d.]+:(\d+)", line))}

    @property
    def http(self) -> str:
        return f"http://127.0.0.1:{self.listening['http']}"


@contextmanager
def motionsim_serve(*args: str) -> Iterator[Service]:
    """Run ``motionsim serve --port 0 --clock virtual ARGS`` until it prints its HTTP line."""
    cmd = [sys.executable, "-m", "motionsim",
           "serve", "--port", "0", "--clock", "virtual", *args]
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    proc = subprocess.Popen(cmd, cwd=ROOT, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)
    lines: list[str] = []
    try:
        deadline = time.monotonic() + START_TIMEOUT_S
        assert proc.stdout is not None
        while time.monotonic() < deadline:
            line = proc.stdout.readline()
            if not line:
                break
            lines.append(line.rstrip())
            if "listening http://" in line:
                break
        service = Service(proc, lines)
        assert "http" in service.listening, "motionsim serve did not start:\n" + "\n".join(lines)
        for _ in range(100):
            try:
                if httpx.get(service.http + "/health", timeout=1).status_code == 200:
                    break
            except httpx.HTTPError:
                pass
            time.sleep(0.05)
        yield service
    finally:
        stop(proc)


DLS_CLIENT = r"""
import json, sys
from dls_pmaclib.dls_pmacremote import PmacEthernetInterface

port = int(sys.argv[1])
p = PmacEthernetInterface(verbose=False, timeout=5.0)
p.setConnectionParams("127.0.0.1", port)
out = {"connect": p.connect()}
def send(cmd):
    resp, ok = p.sendCommand(cmd)
    out.setdefault("log", []).append([cmd, resp, ok])
    return resp
out["cid"] = send("cid")
out["model"] = p.getPmacModel()
out["i16"] = send("i16")
out["setup"] = [send("&1 DEFINE ROT 600"), send("&1 B0"), send("OPEN ROT")]
out["stream"] = [send(f"X{n}") for n in range(1, 21)]
out["close"] = send("CLOSE")
out["pr"] = send("&1 PR")
out["err"] = send("X1")
p.disconnect()
print(json.dumps(out))
"""


def test_dls_pmaclib_connects_defines_and_streams_a_rotary_buffer() -> None:
    pmac_port = free_port()
    with motionsim_serve("--pmac-port", str(pmac_port), "--trio-port", "0") as svc:
        assert svc.listening.get("pmac") == pmac_port, svc.lines
        client = subprocess.run([sys.executable, "-c", DLS_CLIENT, str(pmac_port)],
                                capture_output=True, text=True, timeout=60)
        assert client.returncode == 0, client.stderr
        out = json.loads(client.stdout)
        events = httpx.get(svc.http + "/controllers/pmac/events",
                           params={"type": "line_loaded"}, timeout=5).json()["events"]
    assert out["connect"] is None  # dls-pmaclib returns None on success
    assert re.fullmatch(r"\d+\r\x06", out["cid"])
    assert out["model"] is not None
    assert out["i16"] == "5\r\x06"
    assert all(ok for _, _, ok in out["log"]), out["log"]
    assert out["setup"] == ["\x06"] * 3 and out["close"] == "\x06"
    assert out["stream"] == ["\x06"] * 20
    assert out["pr"] == "20\r\x06"
    assert out["err"] == "\x07ERR005\r"  # a buffered line with no buffer open
    assert [e["text"] for e in events] == [f"X{n}" for n in range(1, 21)]


def _packet(request_type: int, request: int, payload: bytes = b"", length: int | None = None):
    n = len(payload) if length is None else length
    return bytes([request_type, request, 0, 0, 0, 0, n >> 8, n & 0xFF]) + payload


def _read_reply(sock: socket.socket) -> bytes:
    """Read like pmacAsynIPPort: until ACK, or BELL…CR."""
    data = b""
    while True:
        chunk = sock.recv(4096)
        if not chunk:
            return data
        data += chunk
        if data.endswith(b"\x06") or (b"\x07" in data and data.endswith(b"\r")):
            return data


def test_epics_driver_exchange_flush_then_getresponse_with_40_queries() -> None:
    pmac_port = free_port()
    with motionsim_serve("--pmac-port", str(pmac_port), "--trio-port", "0") as svc:
        assert svc.listening.get("pmac") == pmac_port, svc.lines
        with socket.create_connection(("127.0.0.1", pmac_port), timeout=5) as s:
            def write_read(cmd: str) -> bytes:
                s.sendall(_packet(0x40, 0xB3))
                flushed = s.recv(1)
                assert len(flushed) == 1
                s.sendall(_packet(0x40, 0xBF, (cmd + "\n").encode()))
                return _read_reply(s)

            s.sendall(_packet(0x40, 0xBF, b"i6=1 i3=2"))  # the IOC's required I3/I6
            assert _read_reply(s) == b"\x06"
            probe = write_read("")
            cid = write_read("cid")
            queries = (["i16", "i17", "#1P", "#1F", "&1??", "???", "#1?", "M1", "P1", "i124"] * 4)
            assert len(queries) == 40
            poll = write_read(" ".join(queries))
            bad = write_read("i16 FOO i17")
    assert probe == b"\x06"
    assert re.fullmatch(rb"\d+\r\x06", cid)
    lines = poll.split(b"\r")
    assert lines[-1] == b"\x06" and len(lines) == 41, poll
    assert lines[0] == b"5" and lines[1] == b"10"
    assert re.fullmatch(rb"[0-9A-F]{18}", lines[4])  # &1?? : three 24-bit words in hex
    # the queries before the malformed command answer, then the error; no ACK (spec §2.3)
    assert bad == b"5\r\x07ERR003\r"


@pytest.mark.parametrize("n_conn", [2])
def test_two_tcp_connections_are_two_ports_one_may_hold_the_buffer(n_conn: int) -> None:
    """Spec §1.1: buffered lines only from the port that issued OPEN; OPEN from a second
    port while another holds a buffer open → ERR007; nothing stored."""
    pmac_port = free_port()
    with motionsim_serve("--pmac-port", str(pmac_port), "--trio-port", "0") as svc:
        socks = [socket.create_connection(("127.0.0.1", pmac_port), timeout=5)
                 for _ in range(n_conn)]
        a, b = socks

        def ask(s: socket.socket, cmd: str) -> bytes:
            s.sendall(_packet(0x40, 0xBF, cmd.encode()))
            return _read_reply(s)

        assert ask(a, "i6=1 i3=2") == b"\x06"
        assert ask(a, "&1 DEFINE ROT 100") == b"\x06"
        assert ask(a, "OPEN ROT") == b"\x06"
        assert ask(b, "OPEN ROT") == b"\x07ERR007\r"
        assert ask(b, "X5") == b"\x07ERR005\r"
        assert ask(a, "X1") == b"\x06"
        assert ask(a, "CLOSE") == b"\x06"
        rotary = httpx.get(svc.http + "/controllers/pmac/coord/1", timeout=5).json()["rotary"]
        for s in socks:
            s.close()
    assert rotary["lines_ahead"] == 1


def test_lines_over_tcp_show_in_the_log_and_websocket_like_lines_over_http() -> None:
    """Issue 6 §5: the same controller object — a line sent over TCP gives the same events
    (same fields) as one posted to the REST terminal, and they reach WebSocket subscribers."""
    import asyncio

    import websockets

    pmac_port = free_port()
    with motionsim_serve("--pmac-port", str(pmac_port), "--trio-port", "0") as svc:
        http = svc.http + "/controllers/pmac"
        with socket.create_connection(("127.0.0.1", pmac_port), timeout=5) as s:
            def ask(cmd: str) -> bytes:
                s.sendall(_packet(0x40, 0xBF, cmd.encode()))
                return _read_reply(s)

            assert ask("i6=1 i3=2") == b"\x06"  # not "i3=2 &1": & is the AND operator
            assert ask("&1 DEFINE ROT 100 OPEN ROT") == b"\x06"
            assert ask("X1") == b"\x06"
            assert ask("CLOSE") == b"\x06"
        for cmd in ("OPEN ROT", "X2", "CLOSE"):
            body = httpx.post(http + "/terminal", json={"command": cmd}, timeout=5).json()
            assert body["error"] is None, (cmd, body)

        async def subscribe() -> list[dict]:
            url = svc.http.replace("http://", "ws://") + "/controllers/pmac/events"
            async with websockets.connect(url + "?since=0&type=line_loaded") as ws:
                hello = json.loads(await asyncio.wait_for(ws.recv(), 5))
                assert hello["type"] == "epoch"
                return [json.loads(await asyncio.wait_for(ws.recv(), 5)) for _ in range(2)]

        pushed = asyncio.run(subscribe())
        logged = httpx.get(http + "/events", params={"type": "line_loaded"},
                           timeout=5).json()["events"]
    assert [e["text"] for e in logged] == ["X1", "X2"]
    assert set(logged[0]) == set(logged[1])  # the TCP line's event has the HTTP line's fields
    assert pushed == logged
