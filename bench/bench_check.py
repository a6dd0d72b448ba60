"""``motionsim check DIR`` over a generated tree of real-sized program files: wall ms per file.

    .venv/bin/python bench/bench_check.py [--files N] [--repeat R]

The tree (a temporary folder) holds N files spread over the conventions a lab's tree mixes:
PEWIN-style PLCs (``//`` and ``/* */`` comments, ``#Define``, ``#include <axes.h>``), Diamond
``.pmc`` set-up files (``#define``, ``#include "..."``, Windows-1252 comments), ``msi``
templates (``$(AXIS)``, checked with ``-D AXIS=1``... as ``.pmc``; the default value form
keeps them self-contained), motion programs with a refused ``OPEN`` (1 300 ERR005 follow-ons
grouped), and Trio BASIC programs with Shift-JIS comments; 120-400 lines each. The measured
step is one ``motionsim check DIR`` process (start-up and imports included), best of
``--repeat``; beside it, in the same run, ``python -c pass`` (the interpreter start-up alone)
is timed the same way. Target (issue 36): well under 500 ms per file; the figure is wall ms
per file of the whole process. Writes ``bench/results/check.json``.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "bench"))

from results import write  # noqa: E402

MOTIONSIM = Path(sys.executable).parent / "motionsim"


def pewin_plc(k: int) -> str:
    body = "".join(f"IF (M{k % 32 + 1}01=1) // input {j}\n  P{100 + j}=P{100 + j}+1\n"
                   f"ENDIF\n" for j in range(60))
    return (f"/* PLC {k % 30 + 1}: written in PEWIN32PRO\n   interlocks */\n#include <axes.h>\n"
            f"#Define ON 1\nOPEN PLC {k % 30 + 1} CLEAR\n{body}CLOSE\nENABLE PLC {k % 30 + 1}\n")


def diamond_setup(k: int) -> bytes:
    lines = [f"I{m}30={1000 + m} ; gain réglé, moteur {m}" for m in range(1, 33)]
    lines += [f"I{m}{n:02d}=0 ; réglage" for m in range(1, 33) for n in range(11, 14)]
    return ("; set-up\n#define KP I130\n#include \"gains.pmc\"\nKP=1000\n"
            + "\n".join(lines) + "\n").encode("cp1252")


def msi_template(k: int) -> str:
    lines = [f"I$(AXIS=1){n:02d}=$(VALUE={n})" for n in range(10, 99)]
    lines += [f"P$(BASE=1){n:02d}=0" for n in range(10, 99)]
    return "\n".join(lines) + "\n"


def refused_open(k: int) -> str:
    moves = "".join(f"X{j} Y{j % 7}\n" for j in range(300))
    return f"; rotary never defined\n&1\nOPEN ROT\nINC LINEAR\n{moves}CLOSE\n"


def trio(k: int) -> bytes:
    lines = ["' 軸の設定", "BASE(0)"]
    lines += [f"MOVE({j}) ' 移動 {j}" for j in range(150)]
    lines += ["WAIT IDLE"]
    return ("\n".join(lines) + "\n").encode("shift_jis")


def make_tree(root: Path, n: int) -> None:
    (root / "pewin").mkdir()
    (root / "pewin" / "axes.h").write_text("#define AX1 #1\n")
    (root / "dls").mkdir()
    (root / "dls" / "gains.inc").write_text("I131=10\n")
    (root / "dls" / "gains.pmc").write_text('#include "gains.inc"\n')
    (root / "epics").mkdir()
    (root / "progs").mkdir()
    (root / "trio").mkdir()
    makers = [
        lambda k: (root / "pewin" / f"plc{k}.pmc").write_text(pewin_plc(k)),
        lambda k: (root / "dls" / f"setup{k}.pmc").write_bytes(diamond_setup(k)),
        lambda k: (root / "epics" / f"axis{k}.pmc").write_text(msi_template(k)),
        lambda k: (root / "progs" / f"prog{k}.pmc").write_text(refused_open(k)),
        lambda k: (root / "trio" / f"prog{k}.bas").write_bytes(trio(k)),
    ]
    for k in range(n):
        makers[k % len(makers)](k)


def timed(args: list[str]) -> tuple[float, subprocess.CompletedProcess[str]]:
    # as a user's shell runs it: byte-compiled modules cached (this machine's environment
    # sets PYTHONDONTWRITEBYTECODE, which makes every start-up compile motionsim again)
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    t0 = time.perf_counter()
    done = subprocess.run(args, capture_output=True, text=True, timeout=600, env=env)
    return time.perf_counter() - t0, done


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--files", type=int, default=200)
    parser.add_argument("--repeat", type=int, default=3)
    opts = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        make_tree(root, opts.files)
        runs, starts = [], []
        output = ""
        for _ in range(opts.repeat):
            wall, done = timed([str(MOTIONSIM), "check", str(root)])
            if done.returncode not in (0, 1):
                raise SystemExit(f"check failed ({done.returncode}): {done.stderr}")
            runs.append(wall)
            output = done.stdout
            starts.append(timed([sys.executable, "-c", "pass"])[0])
    best = min(runs)
    per_file_ms = best / opts.files * 1000
    print(f"{opts.files} files in {best:.2f} s: {per_file_ms:.1f} ms per file "
          f"(python start-up {min(starts) * 1000:.0f} ms); {len(output.splitlines())} "
          "report lines")
    path = write("check", figures={"files": opts.files, "wall_s": best, "runs_s": runs,
                                   "ms_per_file": per_file_ms,
                                   "report_lines": len(output.splitlines())},
                 references={"python_startup_s": min(starts)},
                 ratios={"ms_per_file": per_file_ms})
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
