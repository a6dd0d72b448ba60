"""The end of ``make bench``: every target of ``bench/targets.py`` with the ratio measured in
``bench/results/``, PASS or SHORT (or MISSING where its bench did not run). A report, never a
failure. ``--readme`` rewrites the README's "Performance" section between its markers.

Run: ``.venv/bin/python bench/summary.py [--readme]``.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from bench.results import RESULTS, ROOT  # noqa: E402
from bench.targets import TARGETS  # noqa: E402

START, END = "<!-- bench:start -->", "<!-- bench:end -->"


def rows() -> list[tuple[str, str, str, str]]:
    """``(what, measured, target, verdict)`` per target."""
    loaded: dict[str, dict] = {}
    out = []
    for t in TARGETS:
        if t.file not in loaded:
            path = RESULTS / f"{t.file}.json"
            loaded[t.file] = json.loads(path.read_text()) if path.exists() else {}
        ratio = loaded[t.file].get("ratios", {}).get(t.key)
        if ratio is None:
            out.append((t.text, "-", f"{t.op} {t.value:g}", "MISSING"))
        else:
            out.append((t.text, f"{ratio:.3g}", f"{t.op} {t.value:g}",
                        "PASS" if t.met(ratio) else "SHORT"))
    return out


def table(lines: list[tuple[str, str, str, str]]) -> str:
    body = ["| measure | measured | target | |", "|---|---|---|---|"]
    body += [f"| {a} | {b} | {c} | {d} |" for a, b, c, d in lines]
    return "\n".join(body)


def update_readme(text: str) -> None:
    readme = ROOT / "README.md"
    s = readme.read_text()
    if START not in s or END not in s:
        raise SystemExit(f"README.md has no {START} ... {END} markers")
    head, rest = s.split(START, 1)
    _, tail = rest.split(END, 1)
    readme.write_text(f"{head}{START}\n{text}\n{END}{tail}")


def _machine_text(machines: list[dict]) -> str:
    """The rest of the table's heading: the platform and Python the figures were taken on,
    the dates, and the range of the 1-minute load beside the benches (a high load means the
    figures were taken beside other work)."""
    parts = []
    for key in ("platform", "python"):
        seen = sorted({str(m[key]) for m in machines if m.get(key)})
        if seen:
            parts.append(("Python " if key == "python" else "") + " / ".join(seen))
    dates = sorted(str(m["date"])[:16].replace("T", " ") for m in machines if m.get("date"))
    if dates:
        parts.append(f"{dates[0]}" + (f" to {dates[-1]}" if dates[-1] != dates[0] else "")
                     + " UTC")
    loads = [float(m["load_1min"]) for m in machines if m.get("load_1min") is not None]
    if loads:
        parts.append(f"1-minute load {min(loads):.1f}-{max(loads):.1f}")
    return "".join(f", {p}" for p in parts)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--readme", action="store_true", help="rewrite README's Performance table")
    args = ap.parse_args()
    lines = rows()
    width = max(len(a) for a, *_ in lines)
    print("\nperformance targets (ratios to same-run references):")
    for a, b, c, d in lines:
        print(f"  {a:<{width}}  {b:>8}  {c:<8}  {d}")
    if args.readme:
        machines = [json.loads(p.read_text()).get("machine", {}) for p in RESULTS.glob("*.json")]
        shas = ", ".join(sorted({m["git_sha"] for m in machines if m.get("git_sha")})) or "?"
        cpus = max((m.get("cpus") or 0 for m in machines), default=0)
        note = f"Last `make bench`: commit {shas}, {cpus} CPUs{_machine_text(machines)}."
        update_readme(f"{note}\n\n{table(lines)}")
        print("README.md Performance section updated")


if __name__ == "__main__":
    main()
