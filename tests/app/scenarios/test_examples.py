"""Every example scenario runs on the real cores and its headline matches the manual."""

from __future__ import annotations

import struct
from pathlib import Path

import pytest
from motionsim.app.scenarios.model import load_scenario, parse_scenario
from motionsim.app.scenarios.outputs import write_outputs
from motionsim.app.scenarios.report import report
from motionsim.app.scenarios.runner import run

EXAMPLES = Path(__file__).resolve().parents[3] / "examples" / "scenarios"


def run_example(name: str, **overrides):
    scn = load_scenario(EXAMPLES / name)
    if overrides:
        raw = dict(scn.raw, **overrides)
        scn = parse_scenario(raw, file=scn.file, base_dir=scn.base_dir)
    result = run(scn)
    return result, report(result)


def test_every_example_is_listed_here():
    tested = {"rotary_breq.yaml", "pr_polling.yaml", "breq_missed.yaml", "m1_sync.yaml",
              "tn20_stall_and_fix.yaml", "trio_feeders.yaml", "lookahead_breaks.yaml",
              "calc_behind.yaml", "plc0_watchdog.yaml", "write_via_terminal.yaml"}  # fmt: skip
    assert {p.name for p in EXAMPLES.glob("*.yaml")} == tested


def test_rotary_breq_host_within_i16_lines_never_starves_slower_one_does():
    _, rep = run_example("rotary_breq.yaml")
    fast = rep["controllers"]["fast"]["cs"][1]
    slow = rep["controllers"]["slow"]["cs"][1]
    assert fast["starvations"] == 0 and fast["time_starved_s"] == 0
    assert fast["lines_executed"] > 800
    assert slow["starvations"] > 10 and slow["time_starved_s"] > 0.05
    slow_eps = [s for s in rep["starvations"] if s["controller"] == "slow"]
    assert {s["cause"] for s in slow_eps} == {"host_latency"}
    assert all(s["host_response_s"] > s["covered_s"] for s in slow_eps)


def test_1ms_moves_outrun_the_default_rti_and_abort_with_a_run_time_error():
    """TUM p339: planning once per 1.33 ms RTI cannot feed 1 ms moves; I8=0 can."""
    _, rep = run_example("calc_behind.yaml")
    slow = rep["controllers"]["default_rti"]["cs"][1]
    fast = rep["controllers"]["fast_rti"]["cs"][1]
    assert slow["run_time_errors"] == 1 and slow["lines_executed"] == 3
    assert slow["starvations"] == 0  # the buffer never ran dry: calculation was the limit
    assert fast["run_time_errors"] == 0 and fast["lines_executed"] == 300
    (ep,) = rep["starvations"]
    assert ep["controller"] == "default_rti" and ep["cause"] == "calculation_fell_behind"
    assert ep["move_s"] < ep["rti_period_s"]
    assert "calculation fell behind" in ep["detail"]
    assert rep["headline"]["run_time_errors"] == 1


def test_pr_polling_with_manual_water_marks_never_starves():
    _, rep = run_example("pr_polling.yaml")
    m = rep["controllers"]["pmac"]["cs"][1]
    assert m["starvations"] == 0
    assert m["lines_executed"] == 2500
    assert 400 <= m["min_lines_ahead"] <= 500
    assert m["breq_missed"] == 0


def test_one_line_breq_routine_misses_breq_and_recheck_does_not():
    result, rep = run_example("breq_missed.yaml")
    once = rep["controllers"]["once"]["cs"][1]
    recheck = rep["controllers"]["recheck"]["cs"][1]
    assert once["breq_missed"] >= 1
    (ep,) = [s for s in rep["starvations"] if s["controller"] == "once"]
    assert ep["cause"] == "breq_missed"
    assert ep["end_s"] == result.t_end  # never fed again
    assert result.hosts["once_host"].done_t is None
    assert recheck["starvations"] == 0 and recheck["breq_missed"] == 0
    assert result.hosts["recheck_host"].done_t is not None


def test_m1_plain_assignment_is_early_and_synchronous_one_is_on_time():
    _, rep = run_example("m1_sync.yaml")
    (plain,) = rep["controllers"]["plain"]["cs"][1]["mvar"]
    (sync,) = rep["controllers"]["sync"]["cs"][1]["mvar"]
    assert plain["sync"] is False and sync["sync"] is True
    # M1=1 runs when calculated, about a whole 200 ms move before X20 starts
    assert plain["lead_s"] > 0.15
    # M1==1 is done at the first RTI (I8 = 2: every 3 servo cycles) at or after the start of
    # blending into X20 (TUM p250): here one servo cycle after it
    period = 3_713_707 / 8_388_608 / 1000
    assert -3 * period < sync["lead_s"] <= 0
    assert sync["lead_s"] == pytest.approx(-period, abs=1e-9)


def test_tn20_program_stalls_axis_0_and_the_ntype_fix_does_not():
    _, rep = run_example("tn20_stall_and_fix.yaml")
    stall = rep["controllers"]["stall"]
    fix = rep["controllers"]["fix"]
    assert stall["axes"][0]["idle_while_blocked_s"] > 0.5
    assert stall["axes"][1]["idle_while_blocked_s"] == 0
    causes = {s["cause"] for s in rep["starvations"] if s["controller"] == "stall"}
    assert causes == {"process_blocked_on_other_axis"}
    # the fix only waits for the servo interrupt that empties its process buffer (each move
    # transits it, TRM "PMOVE"): under one servo period per wait, no axis idle meanwhile
    assert fix["idle_while_blocked_s"] == 0 and fix["starvations"] == 0
    assert fix["time_blocked_s"] <= fix["blocked_intervals"] * 0.001


def test_trio_blind_feeder_stalls_and_ntype_feeder_does_not():
    _, rep = run_example("trio_feeders.yaml")
    per = rep["controllers"]
    assert per["blind"]["axes"][0]["idle_while_blocked_s"] > 0.3
    assert per["ntype"]["idle_while_blocked_s"] == 0
    assert per["ntype"]["blocked_intervals"] == 0
    assert per["buffered"]["idle_while_blocked_s"] > 0.3  # still in program order


def test_dwell_and_rapid_stop_lookahead_without_starving_the_buffer():
    _, rep = run_example("lookahead_breaks.yaml")
    m = rep["controllers"]["pmac"]["cs"][1]
    assert m["starvations"] == 0
    assert m["lookahead_breaks"] == 2
    causes = [s["cause"] for s in rep["starvations"]]
    assert causes == ["lookahead_dwell", "lookahead_rapid"]
    assert all(s["kind"] == "lookahead_break" and s["length_s"] > 0 for s in rep["starvations"])


def test_same_seed_gives_byte_identical_event_log_and_other_seed_does_not():
    a, _ = run_example("rotary_breq.yaml")
    b, _ = run_example("rotary_breq.yaml")
    c, _ = run_example("rotary_breq.yaml", seed=2)
    assert a.to_jsonl() == b.to_jsonl()
    assert a.to_jsonl() != c.to_jsonl()


def test_stop_event_ends_every_controller_at_that_instant():
    result, rep = run_example(
        "breq_missed.yaml", stop_event={"type": "host_irq", "missed": True}
    )
    assert result.stopped_by == "stop_event on once"
    assert result.t_end < 0.05
    assert all(c.now == result.t_end for c in result.controllers.values())


def png_size(path: Path) -> tuple[int, int]:
    head = path.read_bytes()[:24]
    assert head[:8] == b"\x89PNG\r\n\x1a\n"
    return struct.unpack(">II", head[16:24])


def test_outputs_and_plots_are_written(tmp_path):
    result, rep = run_example("tn20_stall_and_fix.yaml")
    paths = write_outputs(result, rep, tmp_path)
    assert set(paths) == {"events.jsonl", "events.csv", "metrics.json",
                          "stall_buffers.png", "fix_buffers.png"}  # fmt: skip
    for name in ("stall_buffers.png", "fix_buffers.png"):
        assert paths[name].stat().st_size > 10_000
        w, h = png_size(paths[name])
        assert w == 1000 and 300 <= h <= 600
    header = paths["events.csv"].read_text().splitlines()[0].split(",")
    assert header[:4] == ["seq", "t", "controller", "type"]
    assert len(paths["events.jsonl"].read_text().splitlines()) == len(
        paths["events.csv"].read_text().splitlines()
    ) - 1


def test_rotary_plot_has_the_figure_size(tmp_path):
    result, rep = run_example("breq_missed.yaml")
    paths = write_outputs(result, rep, tmp_path)
    for name in ("once_cs1_lines_ahead.png", "recheck_cs1_lines_ahead.png"):
        assert paths[name].stat().st_size > 20_000
        assert png_size(paths[name]) == (1000, 600)


@pytest.mark.parametrize("name", sorted(p.name for p in EXAMPLES.glob("*.yaml")))
def test_example_validates(name):
    assert load_scenario(EXAMPLES / name).controllers
