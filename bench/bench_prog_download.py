"""A 10,000-line fixed motion program downloaded over the PMAC Ethernet port, as a host does.

``motionsim serve`` (virtual clock, its own process) and a client process using
``dls-pmaclib``'s ``PmacEthernetInterface.sendSeries`` (one ``GETRESPONSE`` per line, the
reply awaited before the next: the beamline download). The program mixes what real programs
hold: moves with constant and computed values, assignments, WHILE / IF blocks, GOSUBs to
labelled subroutines (every line is parsed, structure-checked and stored). The figure is lines
per second from the first line to the last reply; target >= 2,000 (issue 26). The reference,
same run, is the same client against a bare asyncio server that frames the same packets and
answers at once: what the wire and the client cost alone.

Run: ``.venv/bin/python bench/bench_prog_download.py [n_lines]``; writes
``bench/results/prog_download.json``.
"""

from __future__ import annotations

import asyncio
import json
import socket
import subprocess
import sys
import threading
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import results  # noqa: E402
import served  # noqa: E402

CLIENT = r"""
import json, sys, time
from dls_pmaclib.dls_pmacremote import PmacEthernetInterface

lines = json.loads(open(sys.argv[2]).read())
p = PmacEthernetInterface(verbose=False, timeout=10.0)
p.setConnectionParams("127.0.0.1", int(sys.argv[1]))
error = p.connect()
if error:
    raise SystemExit(f"connect: {error}")
t0 = time.perf_counter()
bad = [r for r in p.sendSeries(list(enumerate(lines))) if not r[0]]
dt = time.perf_counter() - t0
p.disconnect()
print(json.dumps({"seconds": dt, "refused": [(r[2], r[3]) for r in bad[:5]],
                  "n_refused": len(bad)}))
"""


def program(n: int) -> list[str]:
    """``n`` lines: ``OPEN PROG 50``, ``CLEAR``, whole blocks of a repeating pattern padded
    with moves, a subroutine, ``CLOSE``."""
    block = [
        "P1=0", "WHILE (P1 < 4 AND P2 = 0)", "X(P1*2.5) Y{k}.125", "P1=P1+1", "ENDWHILE",
        "IF (P3 !< {k})", "GOSUB 9000", "ELSE", "X{k}.5 Y-{k}.25 Z0.75", "ENDIF",
        "TA10 TS0 TM(P4+20)", "X1.234 Y5.678", "M33==1", "DWELL 0",
    ]
    head, tail = ["OPEN PROG 50", "CLEAR"], ["RETURN", "N9000 X0", "RETURN", "CLOSE"]
    room = n - len(head) - len(tail)
    body = [line.format(k=k % 997) for k in range(room // len(block)) for line in block]
    body += [f"X{i}.5" for i in range(room - len(body))]
    return head + body + tail


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _client(port: int, lines: list[str], work: Path) -> dict:
    path = work / "lines.json"
    path.write_text(json.dumps(lines))
    run = subprocess.run([sys.executable, "-c", CLIENT, str(port), str(path)],
                         capture_output=True, text=True, timeout=600)
    if run.returncode != 0:
        raise RuntimeError(run.stderr[-2000:])
    return json.loads(run.stdout)


def _bare_server(port: int, stop: threading.Event) -> None:
    """Answers every PMAC Ethernet packet (8-byte header + data) at once, with the card's
    version line (what the client's ``connect`` asks first) and the acknowledgement."""

    async def handle(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        try:
            while True:
                head = await reader.readexactly(8)
                length = int.from_bytes(head[6:8], "big")
                if length:
                    await reader.readexactly(length)
                writer.write(b"1.947  \r\x06")
                await writer.drain()
        except (asyncio.IncompleteReadError, ConnectionError):
            writer.close()

    async def main() -> None:
        server = await asyncio.start_server(handle, "127.0.0.1", port)
        async with server:
            while not stop.is_set():
                await asyncio.sleep(0.05)

    asyncio.run(main())


def main() -> None:
    import tempfile

    n = int(sys.argv[1]) if len(sys.argv) > 1 else 10_000
    lines = program(n)
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        port = _free_port()
        argv = [str(served.BIN / "motionsim"), "serve", "--port", "0", "--clock", "virtual",
                "--pmac-port", str(port), "--trio-port", "0"]
        with served.process(argv):
            sim = _client(port, lines, work)
        bare_port = _free_port()
        stop = threading.Event()
        thread = threading.Thread(target=_bare_server, args=(bare_port, stop), daemon=True)
        thread.start()
        served._wait_accepting(f"http://127.0.0.1:{bare_port}", 1e18)
        bare = _client(bare_port, lines, work)
        stop.set()
    rate = len(lines) / sim["seconds"]
    bare_rate = len(lines) / bare["seconds"]
    print(f"download    : {rate:>10,.0f} lines/s  ({len(lines):,} lines over the PMAC port, "
          f"dls-pmaclib sendSeries; target >= 2,000); refused {sim['n_refused']}")
    print(f"bare server : {bare_rate:>10,.0f} lines/s  (same client, answers at once)")
    print(f"ratio       : {rate / bare_rate:.3f}")
    if sim["n_refused"]:
        print("refused:", sim["refused"])
    path = results.write("prog_download",
                         figures={"lines": len(lines), "lines_per_s": rate,
                                  "refused": sim["n_refused"]},
                         references={"bare_server_lines_per_s": bare_rate},
                         ratios={"download_vs_bare": rate / bare_rate})
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
