"""Parameter sweeps: many independent, seeded runs of one scenario over a grid of values.

``--grid 'i16=2,5,8' --grid 'jitter_ms=0,1,3,5'`` gives the cartesian product (12 runs), or a
random sample of it (``sample``). A parameter is named by an alias from the scenario's
``params`` table, by a dotted path (``hosts.0.latency.jitter_ms``), or by a key that occurs
exactly once in the scenario (``i16``). Each run gets its own seed, derived from the scenario
seed and the run's parameter values only — so a run's result does not depend on which worker
ran it, in what order, or how many runs there are: the local process pool, a single process
and a Dask cluster give the same table.
"""

from __future__ import annotations

import copy
import itertools
import json
import random
import zlib
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from .errors import ScenarioError

#: Runs above which a sweep needs an explicit yes.
CONFIRM_ABOVE = 100_000


@dataclass(frozen=True)
class Param:
    name: str
    path: tuple[Any, ...]
    values: tuple[Any, ...]


def portable_raw(scn: Any) -> dict[str, Any]:
    """The scenario data with files inlined (empirical latencies, program files, PLC files),
    so a run needs no file on the worker that runs it."""
    raw = copy.deepcopy(scn.raw)
    for i, h in enumerate(scn.hosts):
        rh = raw["hosts"][i]
        for field in ("latency", "write_latency", "pr_latency"):
            spec = getattr(h, field, None)
            if spec is not None and spec.dist == "empirical" and spec.file is not None:
                rh[field] = {"dist": "empirical", "samples_ms": list(spec.samples_ms or []),
                             "jitter_ms": spec.jitter_ms}  # fmt: skip
        prog = getattr(h, "program", None)
        if prog is not None and prog.file is not None:
            rh["program"] = {"lines": list(prog.lines or [])}
    for cid, spec in scn.controllers.items():
        for i, plc in enumerate(spec.plcs):
            if plc.file is not None:
                rp = raw["controllers"][cid]["plcs"][i]
                rp.pop("file")
                rp["text"] = plc.text
    return raw


def parse_grid_spec(spec: str) -> tuple[str, list[Any]]:
    """``'i16=2,5,8'`` -> ``('i16', [2, 5, 8])``; ``'x=0:10:2'`` is a range (stop included)."""
    name, sep, rest = spec.partition("=")
    name = name.strip()
    if not sep or not name or not rest.strip():
        raise ScenarioError(f"grid {spec!r}: write NAME=V1,V2,... or NAME=START:STOP:STEP")
    if rest.count(":") == 2 and "," not in rest:
        a, b, c = (_scalar(x) for x in rest.split(":"))
        if not all(isinstance(x, int | float) for x in (a, b, c)) or c <= 0 or b < a:
            raise ScenarioError(f"grid {spec!r}: START:STOP:STEP needs numbers, STEP > 0")
        n = int(round((b - a) / c)) + 1
        values = [a + i * c for i in range(n)]
        values = [round(v, 12) if isinstance(v, float) else v for v in values]
        return name, values
    values = [_scalar(x) for x in rest.split(",")]
    if any(v == "" for v in values):
        raise ScenarioError(f"grid {spec!r}: empty value")
    return name, values


def _scalar(text: str) -> Any:
    v = yaml.safe_load(text.strip())
    return "" if v is None else v


def resolve(raw: dict[str, Any], name: str, aliases: dict[str, str]) -> tuple[Any, ...]:
    """The path in the scenario data that parameter ``name`` sets."""
    dotted = aliases.get(name, name)
    if "." in dotted:
        path = tuple(int(p) if p.isdigit() else p for p in dotted.split("."))
        cur: Any = raw
        for part in path[:-1]:
            try:
                cur = cur[part]
            except (KeyError, IndexError, TypeError):
                raise ScenarioError(
                    f"parameter {name!r}: {dotted!r} is not in the scenario", field=dotted
                ) from None
        if not isinstance(cur, dict | list):
            raise ScenarioError(f"parameter {name!r}: {dotted!r} is not in the scenario")
        return path
    found = list(_find_key(raw, dotted, ()))
    if len(found) != 1:
        where = "nowhere" if not found else f"{len(found)} places"
        raise ScenarioError(
            f"parameter {name!r} is found {where} in the scenario; use a dotted path "
            "(hosts.0.latency.ms) or an alias in params",
            field=name,
        )
    return found[0]


def _find_key(node: Any, key: str, path: tuple[Any, ...]) -> Iterator[tuple[Any, ...]]:
    if isinstance(node, dict):
        for k, v in node.items():
            if k == key:
                yield (*path, k)
            yield from _find_key(v, key, (*path, k))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from _find_key(v, key, (*path, i))


def make_params(raw: dict[str, Any], specs: Sequence[str]) -> list[Param]:
    aliases = dict(raw.get("params") or {})
    params = []
    for spec in specs:
        name, values = parse_grid_spec(spec)
        if any(p.name == name for p in params):
            raise ScenarioError(f"grid parameter {name!r} given twice")
        params.append(Param(name, resolve(raw, name, aliases), tuple(values)))
    return params


def count_runs(params: Sequence[Param], replicates: int = 1) -> int:
    n = replicates
    for p in params:
        n *= len(p.values)
    return n


def points(
    params: Sequence[Param], *, sample: int | None = None, seed: int = 0, replicates: int = 1
) -> list[dict[str, Any]]:
    """The runs: ``{name: value, ..., "replicate": r}``; a sample draws without replacement
    from the product without building it."""
    sizes = [len(p.values) for p in params] + [replicates]
    total = count_runs(params, replicates)
    if sample is not None and sample < total:
        picks = sorted(random.Random(f"sample:{seed}").sample(range(total), sample))
        combos = [_unrank(i, sizes) for i in picks]
    else:
        combos = list(itertools.product(*[range(s) for s in sizes]))
    out = []
    for combo in combos:
        row = {p.name: p.values[i] for p, i in zip(params, combo[:-1], strict=True)}
        row["replicate"] = combo[-1]
        out.append(row)
    return out


def _unrank(i: int, sizes: Sequence[int]) -> tuple[int, ...]:
    idx = []
    for s in reversed(sizes):
        idx.append(i % s)
        i //= s
    return tuple(reversed(idx))


def run_seed(base_seed: int, point: dict[str, Any]) -> int:
    """The seed of one run: a function of the scenario seed and the run's values only."""
    key = json.dumps(point, sort_keys=True, default=str)
    return zlib.crc32(f"{base_seed}|{key}".encode()) & 0x7FFFFFFF


def run_point(
    raw: dict[str, Any],
    paths: dict[str, tuple[Any, ...]],
    point: dict[str, Any],
    *,
    file: str | None = None,
    base_dir: str | None = None,
    same_seed: bool = False,
) -> dict[str, Any]:
    """One run of the sweep (runs in any worker): apply ``point``, run, headline metrics."""
    from .model import parse_scenario
    from .report import report
    from .runner import run

    data = copy.deepcopy(raw)
    for name, path in paths.items():
        cur = data
        for part in path[:-1]:
            cur = cur[part]
        cur[path[-1]] = point[name]
    row: dict[str, Any] = dict(point)
    try:
        base_seed = int(data.get("seed", 0) or 0)
    except (TypeError, ValueError):
        row["seed"] = data.get("seed")
        row["error"] = f"{file or '<scenario>'}: seed: {data.get('seed')!r} is not an integer"
        return row
    data["seed"] = base_seed if same_seed else run_seed(base_seed, point)
    row["seed"] = data["seed"]
    try:
        scn = parse_scenario(data, file=file, base_dir=Path(base_dir) if base_dir else None)
        rep = report(run(scn))
    except ScenarioError as exc:
        row["error"] = str(exc)
        return row
    row.update(rep["headline"])
    row.update(per_controller(rep))
    row["error"] = ""
    return row


#: Separates the controller id from the metric in a per-controller column (``slow.time_starved_s``).
SEP = "."


def per_controller(rep: dict[str, Any]) -> dict[str, Any]:
    """Each controller's own headline, its columns prefixed ``<id>.`` (metrics a kind does not
    have are left out)."""
    from .report import headline

    out: dict[str, Any] = {}
    for cid, r in rep["controllers"].items():
        for key, value in headline({cid: r}).items():
            if value is not None:
                out[f"{cid}{SEP}{key}"] = value
    return out


def metric_title(scenario: str, metric: str, controllers: Sequence[str]) -> str:
    """What a heat-map shows: the metric and the controller it is of (or that it combines
    every controller's)."""
    cid, sep, key = metric.partition(SEP)
    if sep and cid in controllers:
        return f"{scenario}: {key} of controller {cid}"
    if len(controllers) == 1:
        return f"{scenario}: {metric} of controller {controllers[0]}"
    return f"{scenario}: {metric}, all controllers ({', '.join(controllers)})"


def _context(mp: Any) -> Any:
    """``fork`` when this process runs one thread: the workers start with every module and
    cache already warm (a spawned worker re-imports and re-builds them, ~0.5-1 s each, a third
    of a 64-run sweep's wall time on 2 cores). ``spawn`` otherwise: a forked child of a process
    with threads (a Dask client, a server) can inherit a lock held by one of them and hang."""
    import threading

    if threading.active_count() == 1 and "fork" in mp.get_all_start_methods():
        return mp.get_context("fork")
    return mp.get_context("spawn")


Executor = Callable[[Callable[..., dict[str, Any]], list[dict[str, Any]]], Iterator[dict[str, Any]]]


def sweep(
    raw: dict[str, Any],
    params: Sequence[Param],
    runs: list[dict[str, Any]],
    *,
    file: str | None = None,
    base_dir: str | None = None,
    workers: int | None = None,
    client: Any = None,
    same_seed: bool = False,
    progress: Callable[[int, int], None] | None = None,
) -> list[dict[str, Any]]:
    """Run every point; rows in run order whatever ran them.

    Args:
        client: a ``distributed.Client`` to run on a Dask cluster; else a local process
            pool of ``workers`` processes (``1`` = in this process).
    """
    paths = {p.name: p.path for p in params}
    kw = {"file": file, "base_dir": base_dir, "same_seed": same_seed}
    results: list[dict[str, Any] | None] = [None] * len(runs)
    done = 0
    if client is not None:
        from distributed import as_completed

        futures = client.map(
            run_point, [raw] * len(runs), [paths] * len(runs), runs, pure=False, **kw
        )
        index = {f.key: i for i, f in enumerate(futures)}
        for fut in as_completed(futures):
            results[index[fut.key]] = fut.result()
            done += 1
            if progress:
                progress(done, len(runs))
    elif workers == 1 or len(runs) <= 1:
        for i, pt in enumerate(runs):
            results[i] = run_point(raw, paths, pt, **kw)  # type: ignore[arg-type]
            done += 1
            if progress:
                progress(done, len(runs))
    else:
        import concurrent.futures as cf
        import multiprocessing as mp

        with cf.ProcessPoolExecutor(max_workers=workers, mp_context=_context(mp)) as pool:
            futs = {
                pool.submit(run_point, raw, paths, pt, **kw): i  # type: ignore[arg-type]
                for i, pt in enumerate(runs)
            }
            for fut in cf.as_completed(futs):
                results[futs[fut]] = fut.result()
                done += 1
                if progress:
                    progress(done, len(runs))
    return [r for r in results if r is not None]


def rows_csv(rows: list[dict[str, Any]]) -> str:
    import csv
    import io

    cols: list[str] = []
    for r in rows:
        for k in r:
            if k not in cols:
                cols.append(k)
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=cols, lineterminator="\n")
    w.writeheader()
    for r in rows:
        w.writerow({k: ("" if r.get(k) is None else r.get(k)) for k in cols})
    return buf.getvalue()


def write_parquet(rows: list[dict[str, Any]], path: Path) -> bool:
    """Parquet when pyarrow is installed; ``False`` otherwise."""
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        return False
    cols: list[str] = []
    for r in rows:
        for k in r:
            if k not in cols:
                cols.append(k)
    table = pa.table({c: [r.get(c) for r in rows] for c in cols})
    pq.write_table(table, path)
    return True


def heatmap(
    rows: list[dict[str, Any]], params: Sequence[Param], metric: str, path: Path, title: str = ""
) -> Path:
    """A heat-map of ``metric`` over the first two parameters (mean over the others and
    over replicates); one parameter gives a line plot."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    fig, ax = plt.subplots(figsize=(7, 5), dpi=100)
    if len(params) >= 2:
        px, py = params[0], params[1]
        grid = np.full((len(py.values), len(px.values)), np.nan)
        for iy, vy in enumerate(py.values):
            for ix, vx in enumerate(px.values):
                vals = [
                    r[metric]
                    for r in rows
                    if r.get(px.name) == vx and r.get(py.name) == vy
                    and isinstance(r.get(metric), int | float)
                ]
                if vals:
                    grid[iy, ix] = float(np.mean(vals))
        im = ax.imshow(grid, origin="lower", aspect="auto", cmap="viridis")
        ax.set_xticks(range(len(px.values)), [str(v) for v in px.values])
        ax.set_yticks(range(len(py.values)), [str(v) for v in py.values])
        ax.set_xlabel(px.name)
        ax.set_ylabel(py.name)
        for iy in range(grid.shape[0]):
            for ix in range(grid.shape[1]):
                if not np.isnan(grid[iy, ix]):
                    ax.text(ix, iy, f"{grid[iy, ix]:.3g}", ha="center", va="center",
                            color="white", fontsize=8)  # fmt: skip
        fig.colorbar(im, ax=ax, label=metric)
    elif params:
        p = params[0]
        means = []
        for v in p.values:
            vals = [r[metric] for r in rows if r.get(p.name) == v
                    and isinstance(r.get(metric), int | float)]  # fmt: skip
            means.append(float(np.mean(vals)) if vals else np.nan)
        ax.plot(range(len(p.values)), means, marker="o")
        ax.set_xticks(range(len(p.values)), [str(v) for v in p.values])
        ax.set_xlabel(p.name)
        ax.set_ylabel(metric)
    ax.set_title(title or metric)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path


__all__ = [
    "CONFIRM_ABOVE",
    "portable_raw",
    "Param",
    "count_runs",
    "heatmap",
    "metric_title",
    "per_controller",
    "make_params",
    "parse_grid_spec",
    "points",
    "resolve",
    "rows_csv",
    "run_point",
    "run_seed",
    "sweep",
    "write_parquet",
]
