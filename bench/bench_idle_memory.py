"""Memory per idle controller (issue 35): 500 PMAC and 500 Trio controllers created over REST
on one ``motionsim serve`` (``MOTIONSIM_MAX_CONTROLLERS=1000``), the service's resident set
read from ``/proc`` before and after each kind. Target: at most 0.25 MB a controller."""

from __future__ import annotations

import gc
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import httpx

sys.path.insert(0, str(Path(__file__).resolve().parent))

from results import write  # noqa: E402
from served import BIN, _wait_accepting  # noqa: E402

N = 500
_URL = re.compile(r"listening (http://127\.0\.0\.1:\d+)")


def rss_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    raise RuntimeError("no VmRSS")


def settle(client: httpx.Client, pid: int) -> float:
    """The RSS once the service is idle again (a few /health turns, then a pause)."""
    for _ in range(5):
        client.get("/health")
    time.sleep(1.0)
    return rss_mb(pid)


def main() -> None:
    env = {**os.environ, "MOTIONSIM_MAX_CONTROLLERS": str(2 * N + 10)}
    proc = subprocess.Popen([str(BIN / "motionsim"), "serve", "--port", "0", "--clock",
                             "virtual", "--pmac-port", "0", "--trio-port", "0"],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            env=env)
    try:
        url = None
        while url is None:
            line = proc.stdout.readline()
            if not line:
                raise RuntimeError("motionsim serve did not start")
            m = _URL.search(line)
            url = m.group(1) if m else None
        _wait_accepting(url, time.monotonic() + 60)
        per: dict[str, float] = {}
        with httpx.Client(base_url=url, trust_env=False, timeout=60) as c:
            before = settle(c, proc.pid)
            for kind in ("pmac", "trio"):
                for i in range(N):
                    r = c.post("/controllers", json={"id": f"{kind}{i}", "kind": kind,
                                                     "clock": {"mode": "virtual"}})
                    r.raise_for_status()
                after = settle(c, proc.pid)
                per[kind] = (after - before) / N
                before = after
        gc.collect()
    finally:
        proc.terminate()
        proc.wait(10)
    for kind, mb in per.items():
        print(f"idle {kind:4s} controller: {mb:.3f} MB (RSS growth / {N})")
    path = write("idle_memory", figures={"mb_per_controller": per, "controllers": N},
                 references={}, ratios={f"mb_per_idle_{k}": v for k, v in per.items()})
    print(f"-> {path}")


if __name__ == "__main__":
    main()
