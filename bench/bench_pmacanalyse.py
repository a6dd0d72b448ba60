"""A full dls-pmacanalyse read of the simulated card, end to end, on a realtime clock.

``motionsim serve`` (realtime, factor 1: what a user points the tool at) in its own process,
``python -m dls_pmacanalyse.dls_pmacanalyse --pmac=bench --tcpip=127.0.0.1:PORT --backup=DIR``
in another. The figure is the **read**: from the tool's first request to the card's last
answer (``--record`` wall times; ~1200 requests: I/P/Q/M variables, M definitions, 512 axis
definitions, PLC/PROG/kinematic listings), target under 5 s on this machine (issue 15). Also
recorded: the tool's whole run (start-up, reading, then its own comparison and HTML report)
and the server's mean answer time per request. ``load_1min`` says how busy the machine was.
A second run on a virtual clock shows what the simulated card's own answer time costs.

Run: ``.venv/bin/python bench/bench_pmacanalyse.py`` (writes ``bench/results/pmacanalyse.json``).
"""

from __future__ import annotations

import json
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import results  # noqa: E402
import served  # noqa: E402

TIMEOUT_S = 300


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def run_once(clock: str, work: Path) -> dict[str, float]:
    port = _free_port()
    record = work / f"{clock}.jsonl"
    argv = [str(served.BIN / "motionsim"), "serve", "--port", "0", "--clock", clock,
            "--pmac-port", str(port), "--trio-port", "0", "--record", str(record)]
    with served.process(argv):
        t0 = time.perf_counter()
        run = subprocess.run(
            [sys.executable, "-m", "dls_pmacanalyse.dls_pmacanalyse", "--pmac=bench",
             f"--tcpip=127.0.0.1:{port}", f"--backup={work / clock}",
             f"--resultsdir={work / (clock + '-html')}"],
            capture_output=True, text=True, timeout=TIMEOUT_S)
        wall = time.perf_counter() - t0
    if run.returncode != 0:
        raise RuntimeError(run.stdout[-2000:] + run.stderr[-2000:])
    rows = [json.loads(line) for line in record.read_text().splitlines()]
    ins = [r for r in rows if r["kind"] == "in"]
    outs = [r for r in rows if r["kind"] == "out"]
    read_s = outs[-1]["wall"] - ins[0]["wall"]
    answer_s = sum(o["wall"] - i["wall"] for i, o in zip(ins, outs, strict=False))
    return {"read_s": read_s, "tool_wall_s": wall, "requests": len(outs),
            "server_ms_per_request": 1000 * answer_s / len(outs)}


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        realtime = run_once("realtime", work)
        virtual = run_once("virtual", work)
    path = results.write(
        "pmacanalyse",
        figures={"realtime": realtime, "virtual": virtual},
        references={"target_s": 5.0},
        ratios={"full_read_s": realtime["read_s"]},
    )
    print(json.dumps({"realtime": realtime, "virtual": virtual}, indent=2))
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
