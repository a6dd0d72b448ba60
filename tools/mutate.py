"""``make mutate``: mutation testing of the decision modules with cosmic-ray.

For each module of ``tools/mutation.toml`` (or those named on the command line) a cosmic-ray
session is created in ``.mutation/`` and every mutant is run against the module's test subset.
cosmic-ray mutates the file in place and restores it after each mutant; this script refuses to
start on a module with uncommitted changes and checks with git that every module is back as it
was at the end. Prints killed / survived per module and lists the survivors that
``[[equivalent]]`` does not explain (mutants inside type annotations, never evaluated under
``from __future__ import annotations``, count as equivalent too). A report, never a failure:
the exit code is 0 unless the tooling itself failed.

    python tools/mutate.py                      # every module
    python tools/mutate.py sim/pmac/rotary.py   # one
"""

from __future__ import annotations

import argparse
import ast
import shlex
import subprocess
import sys
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CONFIG = ROOT / "tools" / "mutation.toml"
WORK = ROOT / ".mutation"
TARGET = 0.90
CR = str(Path(sys.executable).with_name("cosmic-ray"))  # beside this interpreter (the venv)


@dataclass
class Tally:
    module: str
    killed: int = 0
    survived: list[tuple[int, str, str]] = field(default_factory=list)  # line, operator, diff
    equivalent: int = 0
    incompetent: int = 0

    @property
    def scored(self) -> int:
        return self.killed + len(self.survived)

    @property
    def rate(self) -> float:
        return self.killed / self.scored if self.scored else 1.0


def _session(module: str, tests: list[str], timeout_s: float) -> Path:
    WORK.mkdir(exist_ok=True)
    stem = module.replace("/", "_").removesuffix(".py")
    cfg, db = WORK / f"{stem}.toml", WORK / f"{stem}.sqlite"
    command = [sys.executable, "-m", "pytest", "-x", "-q", "-p", "no:cacheprovider",
               "-p", "no:randomly", *tests]
    cfg.write_text(
        "[cosmic-ray]\n"
        f'module-path = "{module}"\n'
        f"timeout = {timeout_s}\n"
        "excluded-modules = []\n"
        f"test-command = {shlex.join(command)!r}\n"
        "\n[cosmic-ray.distributor]\nname = \"local\"\n"
    )
    db.unlink(missing_ok=True)
    subprocess.run([CR, "init", str(cfg), str(db)], cwd=ROOT, check=True)
    subprocess.run([CR, "exec", str(cfg), str(db)], cwd=ROOT, check=True)
    return db


def _annotation_spans(module: str) -> list[tuple[tuple[int, int], tuple[int, int]]]:
    """Source spans of the module's type annotations. With ``from __future__ import
    annotations`` they are never evaluated, so a mutant inside one (``str | None`` made
    ``str - None``) is equivalent by construction."""
    tree = ast.parse((ROOT / module).read_text())
    spans = []
    for node in ast.walk(tree):
        notes = []
        if isinstance(node, ast.arg | ast.AnnAssign) and node.annotation is not None:
            notes.append(node.annotation)
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef) and node.returns:
            notes.append(node.returns)
        spans += [((n.lineno, n.col_offset), (n.end_lineno, n.end_col_offset)) for n in notes]
    return spans


def _tally(module: str, db: Path, equivalent: set[tuple[str, int, str]]) -> Tally:
    from cosmic_ray.work_db import WorkDB, use_db
    from cosmic_ray.work_item import TestOutcome

    tally = Tally(module)
    notes = _annotation_spans(module)
    with use_db(str(db), WorkDB.Mode.open) as work_db:
        for item, result in work_db.completed_work_items:
            (spec,) = item.mutations
            line = spec.start_pos[0]
            if result.test_outcome == TestOutcome.KILLED:
                tally.killed += 1
            elif result.test_outcome == TestOutcome.INCOMPETENT:
                tally.incompetent += 1
            elif (module, line, spec.operator_name) in equivalent or any(
                    a <= tuple(spec.start_pos) <= b for a, b in notes):
                tally.equivalent += 1
            else:
                changed = [d for d in (result.diff or "").splitlines()
                           if d.startswith("+") and not d.startswith("+++")]
                tally.survived.append((line, spec.operator_name, " ".join(changed)[:90]))
    return tally


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("modules", nargs="*", help="modules to mutate (default: all)")
    parser.add_argument("--timeout", type=float, default=60.0, help="seconds per mutant")
    args = parser.parse_args()
    config = tomllib.loads(CONFIG.read_text())
    modules = config["modules"]
    chosen = args.modules or list(modules)
    unknown = [m for m in chosen if m not in modules]
    if unknown:
        parser.error(f"not in {CONFIG.name}: {', '.join(unknown)}")
    dirty = subprocess.run(["git", "status", "--porcelain", "--", *chosen], cwd=ROOT,
                           capture_output=True, text=True, check=True).stdout.strip()
    if dirty:
        parser.error(f"commit or stash these first (they are mutated in place):\n{dirty}")
    equivalent = {(e["module"], int(e["line"]), e["operator"])
                  for e in config.get("equivalent", [])}
    tallies = []
    try:
        for module in chosen:
            db = _session(module, modules[module]["tests"], args.timeout)
            tallies.append(_tally(module, db, equivalent))
    finally:
        subprocess.run(["git", "checkout", "--", *chosen], cwd=ROOT, check=True)
    print(f"\n{'module':<28}{'killed':>8}{'survived':>10}{'equiv.':>8}{'rate':>8}  target")
    for t in tallies:
        mark = "PASS" if t.rate >= TARGET else "SHORT"
        print(f"{t.module:<28}{t.killed:>8}{len(t.survived):>10}{t.equivalent:>8}"
              f"{t.rate:>8.1%}  {mark}")
    for t in tallies:
        for line, op, diff in t.survived:
            print(f"survivor {t.module}:{line} {op}: {diff}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
