"""Regenerate the README's plots from the example scenarios: ``make plots``.

Each entry runs an example in virtual time (deterministic: the same seed gives the same
figure) and copies one of the PNGs ``motionsim run`` writes to the file the README shows, so
the pictures never drift from what the simulator does.

    .venv/bin/python examples/scenarios/readme_plots.py [--dest DIR] [NAME ...]
"""

from __future__ import annotations

import argparse
import shutil
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent

#: README image ← (example scenario, the plot of it that it shows).
PLOTS: dict[str, tuple[str, str]] = {
    "rotary_breq_slow.png": ("rotary_breq.yaml", "slow_cs1_lines_ahead_zoom.png"),
    "plc0_watchdog_long.png": ("plc0_watchdog.yaml", "long_plc0_cs1_lines_ahead.png"),
}


def regenerate(dest: Path, names: list[str] | None = None) -> list[Path]:
    """Write the README images ``names`` (all if None) into ``dest``; their paths."""
    from motionsim.app.scenarios.model import load_scenario
    from motionsim.app.scenarios.plots import plot_run
    from motionsim.app.scenarios.report import report
    from motionsim.app.scenarios.runner import run

    wanted = names or list(PLOTS)
    unknown = [n for n in wanted if n not in PLOTS]
    if unknown:
        raise SystemExit(f"no README plot {', '.join(unknown)}; known: {', '.join(PLOTS)}")
    written = []
    by_scenario: dict[str, list[str]] = {}
    for name in wanted:
        by_scenario.setdefault(PLOTS[name][0], []).append(name)
    for scenario, images in by_scenario.items():
        result = run(load_scenario(HERE / scenario))
        with tempfile.TemporaryDirectory() as tmp:
            made = plot_run(result, report(result), Path(tmp))
            for image in images:
                target = dest / image
                shutil.copyfile(made[PLOTS[image][1]], target)
                written.append(target)
    return written


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dest", type=Path, default=HERE)
    ap.add_argument("names", nargs="*", help=f"images to make (default: {', '.join(PLOTS)})")
    args = ap.parse_args(argv)
    for path in regenerate(args.dest, args.names):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
