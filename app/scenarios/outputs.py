"""Writing a run to disk: the event log (JSON Lines and CSV), the metrics (JSON), the plots."""

from __future__ import annotations

import csv
import io
import json
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .runner import RunResult

if TYPE_CHECKING:
    from .remote import RemoteRun


def events_csv(result: RunResult | RemoteRun, jsonl: str | None = None) -> str:
    """The merged log as CSV: ``seq,t,controller,type`` then every field seen, in order of
    first appearance (deterministic); non-scalar values as JSON. ``jsonl``: the run's
    :meth:`~.runner.RunResult.to_jsonl` when already made."""
    text = result.to_jsonl() if jsonl is None else jsonl
    rows: list[dict[str, Any]] = [json.loads(line) for line in text.splitlines()]
    cols = ["seq", "t", "controller", "type"]
    seen = set(cols)
    for r in rows:
        for k in r:
            if k not in seen:
                seen.add(k)
                cols.append(k)
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(cols)
    for r in rows:
        w.writerow([_cell(r.get(c)) for c in cols])
    return buf.getvalue()


def _cell(v: Any) -> Any:
    if v is None:
        return ""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, dict | list):
        return json.dumps(v, separators=(",", ":"))
    return v


def write_outputs(
    result: RunResult | RemoteRun, rep: dict[str, Any], out_dir: str | Path, *,
    plots: bool = True, window: tuple[float, float] | None = None,
    progress: Callable[[float, float], None] | None = None,
) -> dict[str, Path]:
    """Write ``events.jsonl``, ``events.csv``, ``metrics.json`` and the PNGs (``window``: the
    span of simulated time they show); return paths. ``progress(done, total)``: after each
    of the four steps."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    paths: dict[str, Path] = {}
    step = progress or (lambda done, total: None)
    jsonl = result.to_jsonl()
    p = out / "events.jsonl"
    p.write_text(jsonl, encoding="utf-8")
    paths["events.jsonl"] = p
    step(1, 4)
    p = out / "events.csv"
    p.write_text(events_csv(result, jsonl), encoding="utf-8")
    paths["events.csv"] = p
    step(2, 4)
    p = out / "metrics.json"
    p.write_text(json.dumps(rep, indent=2, default=str) + "\n", encoding="utf-8")
    paths["metrics.json"] = p
    step(3, 4)
    if plots:
        from .plots import plot_run

        for name, path in plot_run(result, rep, out, window).items():
            paths[name] = path
    step(4, 4)
    return paths


__all__ = ["events_csv", "write_outputs"]
