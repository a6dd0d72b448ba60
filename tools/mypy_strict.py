"""``mypy --strict`` over ``sim/``, counted: the figure ``tests/app/test_mypy_strict.py`` keeps
from rising (the recorded counts are ``tests/app/mypy_strict_baseline.json``).

Every import in ``sim/`` is ``motionsim.sim...``, which the editable install maps to the
top-level folder through a package-dir entry mypy cannot follow (the imports would all be
"not found" and every type ``Any``). So mypy runs on a shadow package in a scratch folder,
``motionsim/`` with ``sim`` a symbolic link to the repository's ``sim/``: the imports
resolve, and errors are reported against ``sim/...`` paths.

Run: ``.venv/bin/python tools/mypy_strict.py`` (prints the errors and the counts).
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
import tempfile
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BASELINE = ROOT / "tests" / "app" / "mypy_strict_baseline.json"
#: The parts counted on their own besides the whole of ``sim/`` (see the baseline file).
PARTS = ("sim/pmac/lookahead",)


def run() -> list[str]:
    """The ``error:`` lines of ``mypy --strict`` over ``sim/``, paths as ``sim/...``."""
    with tempfile.TemporaryDirectory(prefix="motionsim-mypy-") as tmp:
        pkg = Path(tmp) / "motionsim"
        pkg.mkdir()
        shutil.copy(ROOT / "motionsim" / "__init__.py", pkg / "__init__.py")
        (pkg / "sim").symlink_to(ROOT / "sim", target_is_directory=True)
        proc = subprocess.run(
            [sys.executable, "-m", "mypy", "--strict", "--no-incremental",
             "--cache-dir", str(Path(tmp) / ".cache"), "--no-error-summary",
             "--hide-error-context", "-p", "motionsim.sim"],
            cwd=tmp, capture_output=True, text=True, check=False,
        )  # fmt: skip
    if proc.returncode not in (0, 1) or "error: " in proc.stderr:
        raise RuntimeError(f"mypy did not run: {proc.stderr.strip() or proc.stdout[-2000:]}")
    return [
        line.removeprefix("motionsim/")
        for line in proc.stdout.splitlines()
        if ": error: " in line
    ]


def counts(errors: list[str]) -> dict[str, int]:
    """``{"sim": all errors, part: errors under part, ...}`` for :data:`PARTS`."""
    paths = Counter(line.split(":", 1)[0] for line in errors)
    out = {"sim": sum(paths.values())}
    for part in PARTS:
        out[part] = sum(n for p, n in paths.items() if p.startswith(part + "/"))
    return out


def baseline() -> dict[str, int]:
    data: dict[str, int] = json.loads(BASELINE.read_text(encoding="utf-8"))["counts"]
    return data


def main() -> int:
    errors = run()
    print("\n".join(errors))
    now, was = counts(errors), baseline()
    for key, n in now.items():
        print(f"{key}: {n} (recorded {was.get(key)})")
    return 1 if any(n > was.get(key, 0) for key, n in now.items()) else 0


if __name__ == "__main__":
    sys.exit(main())
