"""Sweeps: grid parsing, parameter names, seeds; local pool == one process == Dask cluster."""

from __future__ import annotations

from pathlib import Path

import pytest
from motionsim.app.cli import cli
from motionsim.app.scenarios import sweep as sw
from motionsim.app.scenarios.errors import ScenarioError
from motionsim.app.scenarios.model import loads_scenario
from typer.testing import CliRunner

from tests.app.scenarios.fragments import breq_stream

SMALL = breq_stream(
    "name: small\nseed: 5\nduration_s: 0.25\n",
    latency="{dist: normal, mean_ms: 4, sd_ms: 1}",
    moves=200,
    tail="params:\n  latency_ms: hosts.0.latency.mean_ms\n",
)


@pytest.fixture
def small():
    return loads_scenario(SMALL)


def test_grid_specs():
    assert sw.parse_grid_spec("i16=2,5,8") == ("i16", [2, 5, 8])
    assert sw.parse_grid_spec("jitter_ms=0:1:0.25") == ("jitter_ms", [0, 0.25, 0.5, 0.75, 1.0])
    assert sw.parse_grid_spec("recheck_breq=true,false") == ("recheck_breq", [True, False])
    for bad in ("i16", "=1,2", "i16=", "x=1,,2", "x=3:1:1"):
        with pytest.raises(ScenarioError):
            sw.parse_grid_spec(bad)


def test_parameter_by_alias_dotted_path_or_unique_key(small):
    raw = small.raw
    assert sw.resolve(raw, "latency_ms", raw["params"]) == ("hosts", 0, "latency", "mean_ms")
    assert sw.resolve(raw, "hosts.0.lines_per_interrupt", {}) == (
        "hosts", 0, "lines_per_interrupt")  # fmt: skip
    assert sw.resolve(raw, "i16", {}) == ("controllers", "pmac", "config", "i16")
    with pytest.raises(ScenarioError, match="found nowhere"):
        sw.resolve(raw, "i99", {})
    with pytest.raises(ScenarioError, match="not in the scenario"):
        sw.resolve(raw, "hosts.3.latency", {})


def test_points_product_sample_and_seeds(small):
    params = sw.make_params(small.raw, ["i16=2,5,8", "latency_ms=1,3,5,7"])
    assert sw.count_runs(params) == 12
    runs = sw.points(params)
    assert len(runs) == 12 and runs[0] == {"i16": 2, "latency_ms": 1, "replicate": 0}
    sample = sw.points(params, sample=5, seed=1)
    assert len(sample) == 5 and sample == sw.points(params, sample=5, seed=1)
    assert all(r in runs for r in sample)
    # a run's seed depends on its values only, not on its position
    assert sw.run_seed(5, runs[3]) == sw.run_seed(5, dict(reversed(list(runs[3].items()))))
    assert len({sw.run_seed(5, r) for r in runs}) == 12


def test_sweep_shows_starvation_growing_with_latency(small):
    params = sw.make_params(small.raw, ["latency_ms=1,12"])
    rows = sw.sweep(small.raw, params, sw.points(params), workers=1)
    assert [r["latency_ms"] for r in rows] == [1, 12]
    assert rows[0]["time_starved_s"] == 0
    assert rows[1]["time_starved_s"] > 0
    assert all(r["error"] == "" for r in rows)


def test_invalid_point_is_reported_per_row(small):
    params = sw.make_params(small.raw, ["i16=5,12"])
    rows = sw.sweep(small.raw, params, sw.points(params), workers=1)
    assert rows[0]["error"] == ""
    assert "i16 = 12 is above" in rows[1]["error"]


def test_local_pool_and_dask_local_cluster_give_identical_tables(small):
    distributed = pytest.importorskip("distributed")
    params = sw.make_params(small.raw, ["i16=3,6", "latency_ms=2,6"])
    runs = sw.points(params)
    serial = sw.sweep(small.raw, params, runs, workers=1)
    pool = sw.sweep(small.raw, params, runs, workers=2)
    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        dask_rows = sw.sweep(small.raw, params, runs, client=client)
    assert sw.rows_csv(serial) == sw.rows_csv(pool) == sw.rows_csv(dask_rows)
    assert len(serial) == 4


def test_cli_sweep_writes_table_and_heatmap(tmp_path):
    scn = tmp_path / "s.yaml"
    scn.write_text(SMALL)
    out = tmp_path / "out"
    res = CliRunner().invoke(
        cli, ["sweep", str(scn), "--grid", "i16=2,6", "--grid", "latency_ms=1,8",
              "--workers", "1", "--out", str(out)],  # fmt: skip
    )
    assert res.exit_code == 0, res.output
    lines = (out / "sweep.csv").read_text().splitlines()
    assert lines[0].startswith("i16,latency_ms,replicate,seed,time_starved_s")
    assert len(lines) == 5
    assert (out / "heatmap.png").stat().st_size > 10_000


def test_cli_sweep_over_100000_runs_needs_yes(tmp_path):
    scn = tmp_path / "s.yaml"
    scn.write_text(SMALL)
    grid = ["--grid", "i16=0:9:1", "--grid", "i17=10:19:1", "--grid", "latency_ms=0:100:0.1"]
    res = CliRunner().invoke(cli, ["sweep", str(scn), *grid, "--out", str(tmp_path / "o")])
    assert res.exit_code != 0
    assert "100100 runs" in res.output and "--yes" in res.output
    assert not (tmp_path / "o").exists()


def test_cli_run_bad_scenario_names_line_and_runs_nothing(tmp_path):
    scn = tmp_path / "s.yaml"
    scn.write_text(SMALL.replace("mean_ms: 4", "mean_ms: -4"))
    res = CliRunner().invoke(cli, ["run", str(scn), "--out", str(tmp_path / "o")])
    assert res.exit_code == 2
    assert "s.yaml:12: hosts[0].latency.mean_ms" in res.output
    assert not (tmp_path / "o").exists()


def test_cli_run_writes_log_metrics_and_plot(tmp_path):
    scn = tmp_path / "s.yaml"
    scn.write_text(SMALL)
    out = tmp_path / "o"
    res = CliRunner().invoke(cli, ["run", str(scn), "--out", str(out)])
    assert res.exit_code == 0, res.output
    names = {p.name for p in Path(out).iterdir()}
    assert names == {"events.jsonl", "events.csv", "metrics.json", "pmac_cs1_lines_ahead.png",
                     "pmac_cs1_lines_ahead_zoom.png"}  # the whole run, the first refills
    assert "rotary buffers" in res.output


def test_files_are_inlined_for_remote_workers(tmp_path):
    (tmp_path / "lat.txt").write_text("1\n2\n")
    (tmp_path / "prog.pmc").write_text("X1\nX2\n")
    text = SMALL.replace("{dist: normal, mean_ms: 4, sd_ms: 1}", "{dist: empirical, file: lat.txt}")
    text = text.replace("generate: {moves: 200, move_ms: 1, axes: 2}", "file: prog.pmc")
    (tmp_path / "s.yaml").write_text(text)
    from motionsim.app.scenarios.model import load_scenario, parse_scenario

    raw = sw.portable_raw(load_scenario(tmp_path / "s.yaml"))
    assert raw["hosts"][0]["latency"]["samples_ms"] == [1.0, 2.0]
    assert raw["hosts"][0]["program"] == {"lines": ["X1", "X2"]}
    scn = parse_scenario(raw)  # no base_dir: nothing to read
    assert scn.hosts[0].program.to_lines() == ["X1", "X2"]



_FORK_CHECK = """
import json, sys
from motionsim.app.scenarios import sweep as sw
from motionsim.app.scenarios.model import loads_scenario
from tests.app.scenarios.test_sweep import SMALL
raw = loads_scenario(SMALL).raw
params = sw.make_params(raw, ["i16=3,6"])
runs = sw.points(params)
methods = []
real = sw._context
sw._context = lambda mp: methods.append(real(mp).get_start_method()) or real(mp)
pooled = sw.rows_csv(sw.sweep(raw, params, runs, workers=2))
serial = sw.rows_csv(sw.sweep(raw, params, runs, workers=1))
print(json.dumps({"methods": methods, "same": pooled == serial}))
"""


def test_a_single_threaded_process_forks_its_pool_and_gets_the_serial_rows():
    """A forked worker starts with every module warm (a fresh, single-threaded process, as the
    ``motionsim sweep`` command line is)."""
    import json
    import subprocess
    import sys

    root = Path(__file__).resolve().parents[3]
    out = subprocess.run([sys.executable, "-c", _FORK_CHECK], cwd=root, capture_output=True,
                         text=True, timeout=120, check=True).stdout
    assert json.loads(out.splitlines()[-1]) == {"methods": ["fork"], "same": True}


def test_beside_another_thread_the_pool_spawns_and_gets_the_serial_rows(small, monkeypatch):
    """Beside another thread (a server, a Dask client) a fork could inherit a lock that thread
    holds: the pool spawns instead."""
    import threading

    params = sw.make_params(small.raw, ["i16=3,6"])
    runs = sw.points(params)
    serial = sw.sweep(small.raw, params, runs, workers=1)
    methods = []
    real = sw._context
    monkeypatch.setattr(sw, "_context", lambda mp: methods.append(
        real(mp).get_start_method()) or real(mp))
    stop = threading.Event()
    other = threading.Thread(target=stop.wait, daemon=True)
    other.start()
    try:
        spawned = sw.sweep(small.raw, params, runs, workers=2)
    finally:
        stop.set()
        other.join(5)
    assert methods == ["spawn"]
    assert sw.rows_csv(serial) == sw.rows_csv(spawned)


def test_cli_sweep_over_the_seed_shows_the_seed_column_once(tmp_path):
    scn = tmp_path / "s.yaml"
    scn.write_text(SMALL)
    res = CliRunner().invoke(
        cli, ["sweep", str(scn), "--grid", "seed=1,2", "--workers", "1",
              "--out", str(tmp_path / "out")],  # fmt: skip
    )
    assert res.exit_code == 0, res.output
    header = next(line for line in res.output.splitlines() if "seed" in line)
    assert header.count("seed") == 1, res.output
