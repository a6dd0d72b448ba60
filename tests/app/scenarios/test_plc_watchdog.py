"""The PLC 0 watchdog scenario (seed 003; TUM p215, p237; TSRM p57): a PLC 0 longer than the
RTI period leaves the background no processor time, no background cycle reloads the watchdog,
and with I40 = 0 it trips 4096 servo cycles (≈ 1.81 s at 442.7 µs) later; a PLC 0 that fits
never trips but makes the host's PR replies slower.

Times are asserted in servo cycles: every instant the PMAC core emits is a whole servo cycle
and RTIs are the cycles divisible by I8 + 1 (3 by default).
"""

from __future__ import annotations

from pathlib import Path

import pytest
from motionsim.app.scenarios.model import load_scenario, parse_scenario
from motionsim.app.scenarios.outputs import write_outputs
from motionsim.app.scenarios.plots import _card_marks
from motionsim.app.scenarios.report import report
from motionsim.app.scenarios.runner import run
from motionsim.sim.timing import pmac_servo_period_s

EXAMPLE = Path(__file__).resolve().parents[3] / "examples" / "scenarios" / "plc0_watchdog.yaml"


@pytest.fixture(scope="module")
def example():
    result = run(load_scenario(EXAMPLE))
    return result, report(result)


def cycle(result, cid: str, t: float) -> int:
    period = result.controllers[cid].scheduler.period_s
    k = round(t / period)
    assert abs(k * period - t) < 1e-9, f"{t} is not on a servo cycle"
    return k


def only(result, cid: str, typ: str):
    (e,) = result.controllers[cid].log.events(typ)
    return e


def test_a_plc0_longer_than_the_rti_trips_4096_servo_cycles_after_the_last_background_cycle(
    example,
):
    """ENABLE PLC 0 is executed at the end of a background cycle (the ``plc`` event); PLC 0
    first scans at the next RTI, and the housekeeping pass that ends there is the last
    background cycle: from then on every RTI overruns. The trip is 4096 cycles later."""
    result, _ = example
    ctl = result.controllers["long_plc0"]
    period = ctl.scheduler.period_s
    assert period == pytest.approx(442.7e-6, abs=0.05e-6)
    k_enable = cycle(result, "long_plc0", only(result, "long_plc0", "plc").t)
    k_first_rti = (k_enable // 3 + 1) * 3
    trip = only(result, "long_plc0", "watchdog")
    assert cycle(result, "long_plc0", trip.t) == k_first_rti + 4096
    assert trip.t - k_enable * period == pytest.approx(1.81, abs=0.005)
    assert "4096 servo cycles" in trip.fields["reason"]
    (first_overrun, *_) = ctl.log.events("rti_overrun")
    assert cycle(result, "long_plc0", first_overrun.t) == k_first_rti + 3


def test_the_trip_is_explained_by_the_plc0_scan_and_the_rti_period(example):
    result, rep = example
    (ep,) = [s for s in rep["starvations"] if s["kind"] == "watchdog"]
    assert ep["controller"] == "long_plc0" and ep["cause"] == "plc0_too_long"
    assert ep["plc0_statements"] == 500
    assert ep["plc0_scan_s"] == pytest.approx(5e-6 + 500 * 3.3e-6)  # CpuCosts defaults
    assert ep["plc0_scan_s"] > ep["rti_period_s"]
    assert ep["limit_cycles"] == 4096
    trip = only(result, "long_plc0", "watchdog").t
    period = result.controllers["long_plc0"].scheduler.period_s
    assert ep["start_s"] == trip
    assert cycle(result, "long_plc0", ep["last_background_s"]) == cycle(
        result, "long_plc0", trip
    ) - 4096
    assert ep["detail"].startswith(
        "PLC 0 scan of 500 statements ≈ 1655 µs exceeds the RTI period 1328 µs: the background"
        " could not complete a cycle within I40 = 0 → 4096 servo cycles (1.813 s)"
    )
    cpu = rep["controllers"]["long_plc0"]["cpu"]
    assert cpu["watchdog_trip_s"] == trip
    assert cpu["background_cycle_max_s"] == pytest.approx(4096 * period)
    assert rep["headline"]["watchdog_trips"] == 1
    assert rep["headline"]["watchdog_trip_s"] == trip


def test_every_rti_overruns_once_plc0_runs(example):
    result, rep = example
    cpu = rep["controllers"]["long_plc0"]["cpu"]
    ctl = result.controllers["long_plc0"]
    rtis = (cpu["watchdog_trip_s"] - cpu["first_rti_overrun_s"]) / ctl.scheduler.rti_period_s()
    assert cpu["rti_overruns"] == pytest.approx(rtis + 1, abs=1)
    assert cpu["plc0_statements_max"] == 500
    assert cpu["rti_load_max"] > 0.99


def test_the_trip_stops_the_program_the_host_and_the_card(example):
    result, rep = example
    ctl = result.controllers["long_plc0"]
    trip = only(result, "long_plc0", "watchdog")
    after = ctl.log.read(trip.seq).events
    assert [(e.type, dict(e.fields)) for e in after if e.type == "program"] == [
        ("program", {"cs": 1, "state": "aborted", "error": "watchdog"})
    ]
    assert all(e.t == trip.t for e in after if not e.type.startswith("host_"))
    (stopped,) = [e for e in after if e.type == "host_stopped"]
    assert stopped.fields["host"] == "host_long" and "watchdog" in stopped.fields["reason"]
    assert result.hosts["host_long"].done_t is None  # never sent the whole program
    assert ctl.coord(1)["program"]["state"] == "aborted"
    what = rep["controllers"]["long_plc0"]["cpu"]["stopped"]
    assert what[0] == "&1 program aborted (motors killed, no deceleration)"
    assert any("host host_long stopped" in w for w in what)
    # the abort is the trip, not a run-time error of the program
    assert rep["controllers"]["long_plc0"]["cs"][1]["run_time_errors"] == 0


def test_the_buffer_runs_dry_because_the_card_stops_answering_pr(example):
    """Before the trip the host's polls time out; with no answer it never refills."""
    result, rep = example
    (ep,) = [s for s in rep["starvations"] if s["kind"] == "buffer_empty"]
    assert ep["controller"] == "long_plc0"
    assert ep["cause"] == "host_commands_unanswered"
    enabled = only(result, "long_plc0", "plc").t
    trip = only(result, "long_plc0", "watchdog").t
    assert enabled < ep["first_unanswered_s"] < enabled + 0.025  # the next poll after it
    assert ep["end_s"] == trip
    m = rep["controllers"]["long_plc0"]["cs"][1]
    assert m["host_timeouts"] >= 10 and m["lines_executed"] < 1500


def test_a_short_plc0_never_trips_and_the_stream_completes(example):
    result, rep = example
    for cid in ("short_plc0", "no_plc"):
        assert result.controllers[cid].log.events("watchdog", "rti_overrun") == []
        m = rep["controllers"][cid]["cs"][1]
        assert m["lines_executed"] == 1500 and m["starvations"] == 0
        assert m["host_timeouts"] == 0
    cpu = rep["controllers"]["short_plc0"]["cpu"]
    assert cpu["plc0_statements_max"] == 250 and cpu["rti_overruns"] == 0
    assert cpu["cpu_samples"] >= 50
    assert not cpu["watchdog_tripped"]


def test_pr_replies_come_later_with_a_short_plc0(example):
    """Without PLCs the card answers at the end of the background cycle in progress — the next
    servo cycle, or the one after when the 40 µs of command and housekeeping do not fit before
    it; PLC 0 takes ≈ 0.83 ms of each 1.33 ms RTI period, so a PR can wait about one RTI
    period for background time."""
    result, rep = example
    period = result.controllers["no_plc"].scheduler.period_s
    none = rep["controllers"]["no_plc"]["cs"][1]
    short = rep["controllers"]["short_plc0"]["cs"][1]
    assert none["pr_replies"] == short["pr_replies"] > 100
    assert none["pr_reply_mean_s"] < period
    assert none["pr_reply_max_s"] <= period + 40e-6
    assert short["pr_reply_mean_s"] > 1.5 * none["pr_reply_mean_s"]
    assert period < short["pr_reply_max_s"] <= 3 * period + 1e-9


def plc0_replies(statements: int) -> float:
    """Mean PR reply time with a PLC 0 of ``statements`` statements (0: none)."""
    raw = load_scenario(EXAMPLE).raw
    ctl = dict(raw["controllers"]["short_plc0"])
    if statements:
        ctl["plcs"] = [{"plc": 0, "text": "\n".join(["P1=P1+1"] * statements)}]
    else:
        ctl.pop("plcs")
    host = dict(raw["hosts"][1], program={"generate": {"moves": 1000, "move_ms": 2, "axes": 2}})
    scn = parse_scenario(
        dict(raw, duration_s=0.5, controllers={"short_plc0": ctl}, hosts=[host]),
        base_dir=EXAMPLE.parent,
    )
    rep = report(run(scn))
    m = rep["controllers"]["short_plc0"]["cs"][1]
    assert m["pr_replies"] >= 20 and m["host_timeouts"] == 0
    assert rep["headline"]["watchdog_trips"] == 0
    return m["pr_reply_mean_s"]


def test_pr_reply_latency_grows_with_plc0():
    means = [plc0_replies(n) for n in (0, 100, 200, 300, 380)]
    assert means == sorted(means) and means[-1] > 2 * means[0]


def test_the_watchdog_trip_is_marked_on_the_lines_ahead_plot(example, tmp_path):
    result, rep = example
    events = result.events("long_plc0")
    marks = [(t, label) for t, label, _ in _card_marks(events)]
    trip = only(result, "long_plc0", "watchdog").t
    assert (trip, f"watchdog trip {trip:.3f} s") in marks
    assert [label for _, label, _ in _card_marks(result.events("no_plc"))] == []
    paths = write_outputs(result, rep, tmp_path)
    png = paths["long_plc0_cs1_lines_ahead.png"]
    assert png.stat().st_size > 20_000


def test_same_seed_same_log(example):
    result, _ = example
    assert run(load_scenario(EXAMPLE)).to_jsonl() == result.to_jsonl()


def test_i40_sets_the_trip_time_in_a_sweep():
    """A sweep over I40: each servo cycle of I40 moves the trip by one servo cycle."""
    from motionsim.app.scenarios.sweep import Param, portable_raw, sweep

    raw = portable_raw(load_scenario(EXAMPLE))  # PLC files inlined: no file needed to run
    raw = dict(raw, duration_s=1.5, controllers={"long_plc0": raw["controllers"]["long_plc0"]},
               hosts=[raw["hosts"][2]])  # fmt: skip
    param = Param("i40", ("controllers", "long_plc0", "config", "i40"), [])
    rows = sweep(raw, [param], [{"i40": 1000}, {"i40": 2000}], workers=1)
    assert [r["error"] for r in rows] == ["", ""]
    assert [r["watchdog_trips"] for r in rows] == [1, 1]
    period = pmac_servo_period_s(3713707)
    gap = rows[1]["watchdog_trip_s"] - rows[0]["watchdog_trip_s"]
    assert round(gap / period) == 1000 and abs(gap - 1000 * period) < 1e-9


def test_the_summary_compares_the_cards_processors_and_says_what_stopped(example):
    from motionsim.app.scenarios.summary import print_summary, summary_tables
    from rich.console import Console

    _, rep = example
    (cpu,) = [t for t in summary_tables(rep) if str(t.title).endswith("PMAC processor")]
    assert cpu.row_count == 3
    console = Console(record=True, width=250)
    print_summary(rep, console)
    text = console.export_text()
    assert "plc0_too_long" in text and "host_commands_unanswered" in text
    assert "long_plc0: the watchdog tripped; stopped: &1 program aborted" in text


def test_the_load_figure_at_the_end_of_the_run(example):
    """``status()["cpu"]`` at the end: the short PLC 0's share of the RTI period."""
    _, rep = example
    end = rep["controllers"]["short_plc0"]["cpu"]["at_end"]
    scan = 5e-6 + 250 * 3.3e-6
    assert end["rti"] == pytest.approx(scan / (3 * 442.708e-6), rel=0.05)  # + planning
    assert end["background"] == pytest.approx(1 - end["rti"])
    assert rep["controllers"]["long_plc0"]["cpu"]["at_end"] is None  # tripped


def test_faults_after_the_trip_find_a_silent_card_and_the_run_goes_on():
    raw = load_scenario(EXAMPLE).raw
    faults = [
        {"type": "terminal", "controller": "long_plc0", "at_ms": 2200, "command": "&1R"},
        {"type": "set_variable", "controller": "long_plc0", "at_ms": 2300, "name": "P1",
         "value": 1},
    ]  # fmt: skip
    scn = parse_scenario(
        dict(raw, duration_s=2.5, controllers={"long_plc0": raw["controllers"]["long_plc0"]},
             hosts=[raw["hosts"][2]], faults=faults),
        base_dir=EXAMPLE.parent,
    )  # fmt: skip
    result = run(scn)
    ctl = result.controllers["long_plc0"]
    (trip,) = ctl.log.events("watchdog")
    assert trip.t < 2.2 and result.t_end == 2.5
    assert ctl.get_variable("P1") == 0 and ctl.coord(1)["program"]["state"] == "aborted"
