"""Plots and sweep tables a person reads: ``--window``, the default zoom on the first refill
cycles, a legend entry for every shading and mark, the end of the program marked; sweep
columns per controller and a heat-map title that says which controller and metric."""

from __future__ import annotations

import csv
import io

import pytest
from motionsim.app.cli import cli
from motionsim.app.scenarios import plots
from motionsim.app.scenarios import sweep as sw
from motionsim.app.scenarios.plots import parse_window, plot_run, zoom_window
from typer.testing import CliRunner

from tests.app.scenarios.test_examples import EXAMPLES, run_example


@pytest.fixture
def figures(monkeypatch):
    """Every figure the plots close (saved first), to read their legends and limits."""
    seen = []
    close = plots.plt.close

    def keep(fig=None):
        seen.append(fig)
        close(fig)

    monkeypatch.setattr(plots.plt, "close", keep)
    return seen


def _legend_texts(fig) -> list[str]:
    texts = []
    for ax in fig.axes:
        legend = ax.get_legend()
        if legend is not None:
            texts += [t.get_text() for t in legend.get_texts()]
    for legend in fig.legends:
        texts += [t.get_text() for t in legend.get_texts()]
    return texts


def test_window_parsing():
    assert parse_window("0.2:0.5") == (0.2, 0.5)
    assert parse_window(":0.5") == (0.0, 0.5)
    for bad in ("0.5", "0.5:0.2", "a:b", "-1:2", "1:1"):
        with pytest.raises(ValueError, match="--window"):
            parse_window(bad)


def test_default_zoom_covers_the_first_refill_cycles():
    writes = [0.01 * i for i in range(1, 40)]
    assert zoom_window(writes, 1.0) == (0.0, pytest.approx(writes[8] * 1.1))
    assert zoom_window(writes[:5], 1.0) is None  # few refills: the whole run is the zoom


def test_every_shading_and_mark_has_a_legend_entry_and_the_program_end_is_marked(
        tmp_path, figures):
    result, rep = run_example("plc0_watchdog.yaml")
    plot_run(result, rep, tmp_path)
    long_full = next(f for f in figures if "long_plc0" in f.axes[0].get_title()
                     and "(" not in f.axes[0].get_title())
    texts = _legend_texts(long_full)
    for label in ("buffer empty (starved)", "watchdog trip", "card stopped (watchdog)",
                  "PLC 0 enabled", "I16 = 5", "host write"):
        assert any(label in t for t in texts), (label, texts)
    assert any(t.startswith("last move ends") for t in texts)


def test_a_window_limits_every_figure_and_names_itself_in_the_title(tmp_path, figures):
    result, rep = run_example("rotary_breq.yaml")
    paths = plot_run(result, rep, tmp_path, window=(0.3, 0.45))
    assert sorted(paths) == ["fast_cs1_lines_ahead.png", "slow_cs1_lines_ahead.png"]
    for fig in figures:
        assert fig.axes[-1].get_xlim() == pytest.approx((0.3, 0.45))
        assert "(0.300-0.450 s)" in fig.axes[0].get_title()


def test_without_a_window_each_stream_also_gets_a_zoom_on_its_first_refills(tmp_path, figures):
    result, rep = run_example("rotary_breq.yaml")
    paths = plot_run(result, rep, tmp_path)
    assert "slow_cs1_lines_ahead_zoom.png" in paths
    zoom = [f for f in figures if "slow" in f.axes[0].get_title() and "(" in f.axes[0].get_title()]
    (fig,) = zoom
    assert fig.axes[-1].get_xlim()[1] < result.t_end / 4


def test_the_trio_figure_has_a_legend_for_lanes_and_shading(tmp_path, figures):
    result, rep = run_example("tn20_stall_and_fix.yaml")
    plot_run(result, rep, tmp_path)
    stall = next(f for f in figures if "stall" in f.axes[0].get_title())
    texts = _legend_texts(stall)
    assert "axis idle while its process waits" in texts
    assert {"MTYPE occupied", "NTYPE occupied", "process buffer occupied"} <= set(texts)
    assert any(t.startswith("last move ends") for t in texts)


def test_motionsim_run_refuses_a_bad_window_before_running(tmp_path):
    res = CliRunner().invoke(cli, ["run", str(EXAMPLES / "rotary_breq.yaml"), "--window",
                                   "0.5:0.1", "--out", str(tmp_path / "o")])
    assert res.exit_code == 2 and "--window" in res.output
    assert not (tmp_path / "o").exists()


def test_sweep_rows_carry_each_controllers_metrics_prefixed_by_its_id(tmp_path):
    out = tmp_path / "o"
    res = CliRunner().invoke(cli, [
        "sweep", str(EXAMPLES / "rotary_breq.yaml"), "--grid", "i16=5,8", "--workers", "1",
        "--metric", "slow.time_starved_s", "--out", str(out)])
    assert res.exit_code == 0, res.output
    rows = list(csv.DictReader(io.StringIO((out / "sweep.csv").read_text())))
    assert len(rows) == 2
    for r in rows:
        assert float(r["fast.time_starved_s"]) == 0
        assert float(r["slow.time_starved_s"]) > 0
        assert float(r["time_starved_s"]) == pytest.approx(float(r["slow.time_starved_s"]))
    assert (out / "heatmap.png").stat().st_size > 5_000


def test_the_heatmap_title_names_the_controller_and_the_metric():
    ids = ["fast", "slow"]
    assert sw.metric_title("rb", "slow.time_starved_s", ids) == \
        "rb: time_starved_s of controller slow"
    assert sw.metric_title("rb", "time_starved_s", ids) == \
        "rb: time_starved_s, all controllers (fast, slow)"
    assert sw.metric_title("rb", "time_starved_s", ["pmac"]) == \
        "rb: time_starved_s of controller pmac"


def test_an_unknown_sweep_metric_is_refused_with_the_columns(tmp_path):
    res = CliRunner().invoke(cli, [
        "sweep", str(EXAMPLES / "rotary_breq.yaml"), "--grid", "i16=5", "--workers", "1",
        "--metric", "nope", "--out", str(tmp_path / "o")])
    assert res.exit_code == 2
    assert "no metric 'nope'" in res.output and "slow.time_starved_s" in res.output


def test_the_trio_figure_draws_each_move_as_its_own_bar_and_counts_moves_per_axis(
        tmp_path, figures):
    """Back-to-back moves on axis 1 (move_end, the next move_start one servo period later)
    are separate MTYPE bars; each axis's label says how many of its planned moves ran, in red
    when some did not (TN20's fix, as written, skips moves whose NTYPE is busy)."""
    result, rep = run_example("tn20_stall_and_fix.yaml")
    plot_run(result, rep, tmp_path)
    for name in ("stall", "fix"):
        fig = next(f for f in figures if f": {name} " in f.axes[0].get_title())
        for ax, (axis, m) in zip(fig.axes, sorted(rep["controllers"][name]["axes"].items()),
                                 strict=True):
            (mtype,) = [c for c in ax.collections if c.get_gid() == "MTYPE"]
            assert len(mtype.get_paths()) == m["moves_done"]
            label = ax.get_ylabel()
            assert label == f"axis {axis}\n{m['moves_done']} of {m['moves_planned']} moves"
            short = m["moves_done"] < m["moves_planned"]
            assert (ax.yaxis.label.get_color() == "tab:red") is short
    fix = rep["controllers"]["fix"]["axes"]
    assert any(m["moves_done"] < m["moves_planned"] for m in fix.values())
    stall = rep["controllers"]["stall"]["axes"]
    assert [m["moves_done"] for m in stall.values()] == [6, 6]


def test_scenario_comments_state_the_values_they_describe():
    """rotary_breq.yaml's header gives each host's BREQ latency and jitter: the same numbers
    as its hosts."""
    import yaml

    path = EXAMPLES / "rotary_breq.yaml"
    text = path.read_text()
    header = " ".join(line.lstrip("# ") for line in text.splitlines() if line.startswith("#"))
    for host in yaml.safe_load(text)["hosts"]:
        lat = host["latency"]
        assert f"{lat['ms']:g} ms ± {lat['jitter_ms']:g} ms" in header, host["name"]


def test_a_scenario_that_sets_up_a_gather_gets_the_recording_plotted(tmp_path, figures):
    """A scenario's ``setup`` commands can start the card's data gathering (docs/pmac.md):
    the run's plots then include ``<controller>_recording.png``, one panel per source."""
    import copy

    from motionsim.app.scenarios.model import parse_scenario
    from motionsim.app.scenarios.outputs import write_outputs
    from motionsim.app.scenarios.report import report
    from motionsim.app.scenarios.runner import run

    from tests.app.scenarios.test_examples import load_scenario

    scn = load_scenario(EXAMPLES / "breq_missed.yaml")
    raw = copy.deepcopy(scn.raw)
    raw["controllers"]["recheck"]["setup"] = [
        "&1 #1->1000X #2->1000Y", "I5001=$800088 I5002=$800108 I5050=3 I5049=4",
        "DEFINE GATHER 20000", "GATHER"]
    scn = parse_scenario(raw, file=scn.file, base_dir=scn.base_dir)
    result = run(scn)
    rec = result.controllers["recheck"].recording()
    assert rec.names == ("I5001", "I5002") and len(rec.cycles) > 100
    assert all(b - a == 4 for a, b in zip(rec.cycles, rec.cycles[1:], strict=False))
    paths = write_outputs(result, report(result), tmp_path)
    assert "recheck_recording.png" in paths and "once_recording.png" not in paths
    assert paths["recheck_recording.png"].stat().st_size > 0
    fig = next(f for f in figures if f is not None and f.axes
               and f.axes[0].get_title().startswith(f"{scn.name}: recheck gather"))
    assert [ax.get_ylabel() for ax in fig.axes] == ["I5001", "I5002"]
