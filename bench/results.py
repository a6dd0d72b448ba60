"""One place that writes ``bench/results/<name>.json``: the figures, the same-run references
they are compared with, the ratios the summary checks, and the machine and commit they were
measured on (figures on a shared 2-core machine vary by ±30 % between runs; a ratio to a
reference measured in the same run does not)."""

from __future__ import annotations

import datetime
import json
import os
import platform
import subprocess
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "bench" / "results"


def machine() -> dict[str, Any]:
    """What the figures were measured on."""
    try:
        sha = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, text=True,
                             capture_output=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        sha = None
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else None
    return {
        "python": platform.python_version(),
        "platform": platform.platform(),
        "cpus": os.cpu_count(),
        "load_1min": load,
        "git_sha": sha,
        "date": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
    }


def write(name: str, *, figures: dict[str, Any], references: dict[str, Any],
          ratios: dict[str, float], **extra: Any) -> Path:
    """Write ``bench/results/<name>.json``; ``ratios`` are what ``bench/summary.py`` checks
    (keys named in ``bench/targets.py``)."""
    RESULTS.mkdir(parents=True, exist_ok=True)
    path = RESULTS / f"{name}.json"
    body = {"figures": figures, "references": references, "ratios": ratios,
            "machine": machine(), **extra}
    path.write_text(json.dumps(body, indent=2, default=float) + "\n")
    return path


def p(values: list[float], q: float) -> float:
    """The ``q`` quantile (0..1) of ``values`` (nearest rank)."""
    if not values:
        return float("nan")
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, max(0, round(q * (len(ordered) - 1))))]
