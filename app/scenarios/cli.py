"""``motionsim run`` and ``motionsim sweep`` (registered on the main CLI by :func:`register`).

Heavy imports (matplotlib, the cores, dask) happen inside the commands so ``motionsim --help``
stays fast.
"""

from __future__ import annotations

import contextlib
import json
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Annotated, Any

import typer


def _fail(message: str, code: int = 2) -> typer.Exit:
    typer.echo(f"motionsim: {message}", err=True)
    return typer.Exit(code)


def run_command(
    scenario: Annotated[Path, typer.Argument(metavar="SCENARIO", help="Scenario YAML file.")],
    out: Annotated[Path | None, typer.Option(
        "--out", "-o", help="Output folder [default: out/<scenario name>].")] = None,
    seed: Annotated[int | None, typer.Option(help="Override the scenario's seed.")] = None,
    plots: Annotated[bool, typer.Option("--plots/--no-plots", help="Write PNG plots.")] = True,
    window: Annotated[str | None, typer.Option(
        metavar="START:END", help="Plot only this span of simulated seconds, e.g. 0.2:0.5 "
        "[default: the whole run, plus a zoom on the first refill cycles].")] = None,
    open_: Annotated[bool, typer.Option("--open", help="Show the plots when done.")] = False,
    force: Annotated[bool, typer.Option(
        "--force", help="Write into an --out folder that holds another scenario's run.")
    ] = False,
    realtime: Annotated[bool, typer.Option(
        "--realtime", help="Play it on a running server (wall-clock time) instead.")] = False,
    server: Annotated[str, typer.Option(help="Server for --realtime.")] = "http://127.0.0.1:8000",
    factor: Annotated[float, typer.Option(help="Realtime speed-up for --realtime.")] = 1.0,
    id_prefix: Annotated[str | None, typer.Option(
        "--id-prefix", help="With --realtime: server ids are PREFIX + the scenario's ids "
        "[default: '<scenario name>-'].")] = None,
    replace: Annotated[bool, typer.Option(
        "--replace", help="With --realtime: delete and re-create server controllers that "
        "already have those ids (their programs and variables are lost).")] = False,
) -> None:
    """Run a what-if scenario in virtual time: summary table, event log (JSON Lines + CSV),
    metrics.json and PNG plots in the output folder. With --realtime the scenario plays on a
    running server and the same files are written from the server's event logs."""
    from .errors import ScenarioError
    from .model import load_scenario, parse_scenario

    wall0 = time.perf_counter()
    span = None
    if window is not None:
        from .plots import parse_window

        try:
            span = parse_window(window)
        except ValueError as exc:
            raise _fail(str(exc)) from None
    try:
        scn = load_scenario(scenario)
        if seed is not None:
            raw = dict(scn.raw)
            raw["seed"] = seed
            scn = parse_scenario(raw, file=scn.file, base_dir=scn.base_dir)
    except ScenarioError as exc:
        raise _fail(str(exc)) from None
    out_dir = out or Path("out") / scn.name
    replacing = _previous_run(out_dir, scn.name, force)
    if realtime:
        from .remote import play

        try:
            with _progress(f"play {scn.name}", "simulated s") as played:
                rep, result = play(scn, server, factor=factor, prefix=id_prefix,
                                   replace=replace, progress=played)
        except ScenarioError as exc:  # the server's answer, not the file's: no file prefix
            raise _fail(str(exc) if exc.file else exc.message, 1) from None
        from .summary import print_summary

        print_summary(rep)
        paths = _write(result, rep, out_dir, plots, span, replacing, scn.name)
        typer.echo(f"played {result.t_end:.3f} s in {time.perf_counter() - wall0:.3f} s wall "
                   f"(realtime); wrote {len(paths)} files to {out_dir}")
    else:
        from .report import report
        from .runner import run
        from .summary import print_summary

        try:
            with _progress(f"run {scn.name}", "simulated s") as advance:
                result = run(scn, progress=advance)
        except ScenarioError as exc:
            raise _fail(str(exc)) from None
        with _progress(f"analyse {scn.name}", "controllers") as analysed:
            rep = report(result, progress=analysed)
        paths = _write(result, rep, out_dir, plots, span, replacing, scn.name)
        print_summary(rep)
        typer.echo(
            f"simulated {result.t_end:.3f} s in {time.perf_counter() - wall0:.3f} s wall "
            f"({result.stopped_by}; the simulation itself {result.wall_s:.3f} s); "
            f"wrote {len(paths)} files to {out_dir}"
        )
    if span is not None and span[0] >= result.t_end:
        typer.echo(f"motionsim: --window starts after the run ended ({result.t_end:.3f} s)",
                   err=True)
    if open_ and plots:
        _show([p for n, p in paths.items() if n.endswith(".png")], out_dir)


def _write(result: Any, rep: dict[str, Any], out_dir: Path, plots: bool,
           span: tuple[float, float] | None, replacing: bool, name: str) -> dict[str, Path]:
    """The run's files (events, metrics, plots) into ``out_dir``, with a progress bar."""
    from .outputs import write_outputs

    if replacing:
        typer.echo(f"motionsim: replacing the earlier run of {name} in {out_dir}", err=True)
    try:
        with _progress(f"write {name}", "files") as wrote:
            return write_outputs(result, rep, out_dir, plots=plots, window=span,
                                 progress=wrote)
    except OSError as exc:
        raise _fail(f"cannot write to {exc.filename or out_dir}: {exc.strerror}", 1) from None


#: What a folder holds once a run was written into it (``metrics.json`` names the scenario).
_RUN_MARKER = "metrics.json"


def _previous_run(out_dir: Path, name: str, force: bool) -> bool:
    """Whether ``out_dir`` holds an earlier run of scenario ``name`` (to be replaced, which
    the command then says). A run of another scenario there is refused unless ``force``:
    two runs never overwrite each other silently."""
    marker = out_dir / _RUN_MARKER
    if not marker.is_file():
        return False
    try:
        earlier = json.loads(marker.read_text(encoding="utf-8")).get("scenario")
    except (OSError, ValueError, AttributeError):
        earlier = None
    if earlier != name and not force:
        raise _fail(f"{out_dir} holds a run of scenario {earlier or '(unknown)'!s}; "
                    f"choose another --out, or pass --force to overwrite it")
    return True


@contextlib.contextmanager
def _progress(what: str, unit: str) -> Iterator[Callable[[float, float], None]]:
    """A Rich progress bar on the terminal (stderr); nothing when stderr is not a terminal."""
    from rich.console import Console
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    console = Console(stderr=True)
    with Progress(
        TextColumn("{task.description}"), BarColumn(),
        TextColumn("{task.completed:.3f} / {task.total:.3f} " + unit), TimeElapsedColumn(),
        console=console, transient=True, disable=not console.is_terminal,
    ) as bar:  # fmt: skip
        task = bar.add_task(what, total=1.0)  # the real total comes with the first report

        def advance(done: float, total: float) -> None:
            bar.update(task, completed=done, total=total)

        yield advance


def _show(pngs: list[Path], out_dir: Path) -> None:
    """Open the plots in the desktop's viewer; with no display, say where they are."""
    import os
    import webbrowser

    has_display = sys.platform in ("darwin", "win32") or any(
        os.environ.get(v) for v in ("DISPLAY", "WAYLAND_DISPLAY"))
    opened = False
    if has_display:
        try:
            opened = all(webbrowser.open(p.resolve().as_uri()) for p in pngs)
        except webbrowser.Error:
            opened = False
    if not opened:
        listed = "\n".join(f"  {p}" for p in pngs)
        typer.echo(f"motionsim: --open: no display to show the plots on; they are in "
                   f"{out_dir.resolve()}:\n{listed}", err=True)


def sweep_command(
    scenario: Annotated[Path, typer.Argument(metavar="SCENARIO", help="Scenario YAML file.")],
    grid: Annotated[list[str], typer.Option(
        "--grid", "-g", metavar="NAME=V1,V2,...",
        help="A parameter and its values (repeat). NAME: an alias from the scenario's params, "
             "a dotted path (hosts.0.latency.ms) or a key found once in the file. "
             "START:STOP:STEP is a range.")],
    out: Annotated[Path | None, typer.Option(
        "--out", "-o", help="Output folder [default: out/<scenario name>-sweep].")] = None,
    metric: Annotated[str | None, typer.Option(
        help="Metric for the heat-map [default: the scenario's metric]: a headline column "
             "(all controllers) or one controller's, e.g. slow.time_starved_s.")] = None,
    sample: Annotated[int | None, typer.Option(
        help="Run a random sample of this many points instead of the whole product.")] = None,
    replicates: Annotated[int, typer.Option(
        help="Runs per point, each with its own seed.")] = 1,
    same_seed: Annotated[bool, typer.Option(
        "--same-seed", help="Every run uses the scenario's seed (common random numbers).")] = False,
    workers: Annotated[int | None, typer.Option(
        help="Local worker processes [default: CPU count]; 1 = in this process.")] = None,
    scheduler: Annotated[str | None, typer.Option(
        metavar="tcp://HOST:8786", help="Run on this Dask distributed scheduler.")] = None,
    yes: Annotated[bool, typer.Option(
        "--yes", "-y", help="Run even when the grid has more than 100 000 runs.")] = False,
) -> None:
    """Run a scenario over a grid of parameters; CSV (and Parquet) table and a heat-map."""
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TimeRemainingColumn

    from . import sweep as sw
    from .errors import ScenarioError
    from .model import load_scenario

    wall0 = time.perf_counter()
    try:
        scn = load_scenario(scenario)
        raw = sw.portable_raw(scn)
        params = sw.make_params(raw, grid)
    except ScenarioError as exc:
        exc.file = exc.file or str(scenario)  # a grid error is about this file's fields
        raise _fail(str(exc)) from None
    if replicates < 1:
        raise _fail("--replicates must be >= 1")
    total = sw.count_runs(params, replicates)
    n = min(total, sample) if sample else total
    if n > sw.CONFIRM_ABOVE and not yes:
        if sys.stdin.isatty():
            typer.confirm(f"{n} runs — go ahead?", abort=True)
        else:
            raise _fail(f"the sweep has {n} runs (more than {sw.CONFIRM_ABOVE}); pass --yes")
    runs = sw.points(params, sample=sample, seed=scn.seed, replicates=replicates)
    metric = metric or scn.metric
    client = None
    if scheduler:
        try:
            from distributed import Client
        except ImportError:
            msg = ("--scheduler needs dask[distributed]: pip install 'dask[distributed]' "
                   "(or install motionsim with its cluster extra: pip install '.[cluster]' "
                   "from a checkout)")
            raise _fail(msg) from None
        client = Client(scheduler)
    console = Console(stderr=True)
    try:
        with Progress(
            "[progress.description]{task.description}", BarColumn(), MofNCompleteColumn(),
            TimeRemainingColumn(), console=console, disable=not console.is_terminal,
        ) as bar:  # fmt: skip
            task = bar.add_task(f"sweep {scn.name}", total=len(runs))
            rows = sw.sweep(
                raw, params, runs, file=scn.file,
                base_dir=str(scn.base_dir) if scn.base_dir else None,
                workers=workers, client=client, same_seed=same_seed,
                progress=lambda done, _total: bar.update(task, completed=done),
            )  # fmt: skip
    finally:
        if client is not None:
            client.close()
    columns = sorted({k for r in rows for k in r if not r.get("error")})
    if any(not r.get("error") for r in rows) and metric not in columns:
        raise _fail(f"{scenario}: no metric {metric!r}; columns: {', '.join(columns)}")
    out_dir = out or Path("out") / f"{scn.name}-sweep"
    if (out_dir / "sweep.csv").is_file():
        typer.echo(f"motionsim: replacing the earlier sweep in {out_dir}", err=True)
    out_dir.mkdir(parents=True, exist_ok=True)
    (out_dir / "sweep.csv").write_text(sw.rows_csv(rows), encoding="utf-8")
    wrote = ["sweep.csv"]
    if sw.write_parquet(rows, out_dir / "sweep.parquet"):
        wrote.append("sweep.parquet")
    sw.heatmap(rows, params, metric, out_dir / "heatmap.png",
               title=sw.metric_title(scn.name, metric, list(scn.controllers)))
    wrote.append("heatmap.png")
    _print_rows(rows, params, metric, console=Console())
    errors = [r for r in rows if r.get("error")]
    typer.echo(f"{len(rows)} runs in {time.perf_counter() - wall0:.3f} s wall; "
               f"wrote {', '.join(wrote)} to {out_dir}")
    if errors:
        raise _fail(f"{len(errors)} runs failed; first: {errors[0]['error']}", 1)


def _print_rows(rows: list[dict[str, Any]], params: list[Any], metric: str, console: Any) -> None:
    from rich.table import Table

    t = Table(title=f"sweep: {metric}")
    # the run's seed once: a sweep over ``seed`` already has it as a grid column
    columns = list(dict.fromkeys([*(p.name for p in params), "seed"]))
    for name in columns:
        t.add_column(name, justify="right")
    t.add_column(metric, justify="right")
    for r in rows[:50]:
        v = r.get(metric)
        t.add_row(*[str(r.get(name)) for name in columns],
                  f"{v:.6g}" if isinstance(v, float) else str(v))  # fmt: skip
    if len(rows) > 50:
        t.caption = f"{len(rows) - 50} more rows in sweep.csv"
    console.print(t)


def register(cli: typer.Typer) -> None:
    """Add ``run`` and ``sweep`` to the ``motionsim`` command."""
    cli.command("run")(run_command)
    cli.command("sweep")(sweep_command)


__all__ = ["register", "run_command", "sweep_command"]
