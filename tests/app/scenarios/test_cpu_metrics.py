"""Processor metrics and the watchdog diagnosis from hand-built logs (no core needed)."""

from __future__ import annotations

import pytest
from motionsim.app.scenarios.cpu_metrics import cpu_metrics, cpu_trace
from motionsim.app.scenarios.diagnosis import diagnose_watchdog
from motionsim.app.scenarios.report import pmac_report

from tests.app.scenarios.logbuilder import Feed

SERVO = 442.7e-6
RTI = 3 * SERVO


def sample(feed: Feed, t: float, stmts: int, cycle_s: float = SERVO, servo: float = 0.0) -> Feed:
    return feed.at(t, "cpu_sample", servo=servo, rti=0.5, background=0.5,
                   background_cycle_s=cycle_s, plc0_statements=stmts)  # fmt: skip


def tripped(stmts: int = 500, lines: int = 0) -> Feed:
    f = Feed()
    f.at(0.1, "plc", plc=0, state="enabled")
    for k in range(lines):
        f.at(0.1 + k * 0.002, "line_calculated", cs=1, n=k + 1)
    sample(f, 0.2, stmts, 2 * SERVO)
    f.at(0.2005, "rti_overrun", over_s=1e-4).at(0.2018, "rti_overrun", over_s=2e-4)
    f.at(0.3, "host_pr", host="h", cs=1, lines_ahead=5, reply_s=0.0009)
    f.at(0.31, "host_timeout", host="h", cs=1, command="&1PR", waited_s=0.1)
    f.at(1.9, "watchdog", reason="no background cycle completed within 4096 servo cycles (I40)")
    f.at(1.9, "program", cs=1, state="aborted", error="watchdog")
    f.at(1.9, "mvar", name="M5", value=0.0, sync=False)
    f.at(1.95, "host_stopped", host="h", cs=1, reason="the watchdog has tripped")
    return f


def test_cpu_metrics_count_overruns_replies_and_the_trip():
    m = cpu_metrics(cpu_trace(tripped().events()))
    assert m["rti_overruns"] == 2 and m["first_rti_overrun_s"] == 0.2005
    assert m["plc0_statements_max"] == 500
    assert m["background_cycle_max_s"] == pytest.approx(2 * SERVO)
    assert m["pr_replies"] == 1 and m["pr_reply_mean_s"] == 0.0009
    assert m["host_timeouts"] == 1
    assert m["watchdog_tripped"] and m["watchdog_trip_s"] == 1.9
    assert m["stopped"] == [
        "&1 program aborted (motors killed, no deceleration)",
        "outputs off: M5",
        "host h stopped at 1.950000 s (the card answers nothing)",
        "the card: no command answered, no task run until reset (power cycle)",
    ]


def test_no_trip_no_stop():
    f = Feed()
    sample(f, 0.1, 100)
    m = cpu_metrics(cpu_trace(f.events()))
    assert not m["watchdog_tripped"] and m["stopped"] == [] and m["rti_overruns"] == 0


def test_the_report_diagnoses_a_plc0_too_long_for_the_rti():
    rep = pmac_report(tripped().events(), 2.0, controller="c", servo_period_s=SERVO,
                      rti_period_s=RTI)  # fmt: skip
    (ep,) = [s for s in rep["starvation_list"] if s.kind == "watchdog"]
    assert ep.cause == "plc0_too_long" and ep.start == 1.9 and ep.end == 2.0
    assert ep.facts["plc0_statements"] == 500 and ep.facts["limit_cycles"] == 4096
    assert ep.facts["last_background_s"] == pytest.approx(1.9 - 4096 * SERVO)
    assert "PLC 0 scan of 500 statements ≈ 1655 µs exceeds the RTI period 1328 µs" in ep.detail
    assert "2 RTIs overran from 0.200500 s" in ep.detail
    assert "PLC 0 was enabled at 0.100000 s" in ep.detail
    assert rep["cpu"]["background_cycle_max_s"] == pytest.approx(4096 * SERVO)
    assert rep["cs"][1]["run_time_errors"] == 0  # the trip's abort is not a run-time error


def test_i40_and_costs_come_from_the_config():
    config = {"cpu_plc_statement_us": 10, "i40": 500}
    rep = pmac_report(tripped(stmts=200).events(), 2.0, controller="c", servo_period_s=SERVO,
                      rti_period_s=RTI, config=config)  # fmt: skip
    (ep,) = [s for s in rep["starvation_list"] if s.kind == "watchdog"]
    assert ep.facts["plc0_scan_s"] == pytest.approx(5e-6 + 200 * 10e-6)
    assert ep.facts["limit_cycles"] == 500 and ep.cause == "plc0_too_long"
    assert "within I40 = 500 servo cycles" in ep.detail


def test_plc0_plus_move_planning_over_the_rti_is_named_as_such():
    ep = diagnose_watchdog(
        "c", 1.9, 2.0, limit_cycles=4096, i40=0, servo_period_s=SERVO, rti_period_s=RTI,
        servo_share=0.0, plc0_statements=380, plc0_scan_s=5e-6 + 380 * 3.3e-6,
        planning_s=100e-6,
    )  # fmt: skip
    assert ep.cause == "rti_tasks_too_long"
    assert ep.detail.startswith(
        "PLC 0 scan of 380 statements ≈ 1259 µs plus move planning ≈ 100 µs per RTI exceed"
    )


def test_servo_load_shrinks_the_room_left_for_the_rti():
    ep = diagnose_watchdog(
        "c", 1.9, 2.0, limit_cycles=4096, i40=0, servo_period_s=SERVO, rti_period_s=RTI,
        servo_share=0.2, plc0_statements=350, plc0_scan_s=5e-6 + 350 * 3.3e-6,
    )  # fmt: skip
    assert ep.cause == "plc0_too_long"
    assert "(1062 µs left after the servo task)" in ep.detail


def test_without_plc0_the_background_was_starved_by_other_work():
    ep = diagnose_watchdog(
        "c", 1.9, 2.0, limit_cycles=4096, i40=0, servo_period_s=SERVO, rti_period_s=RTI,
        servo_share=0.99, plc0_statements=None, plc0_scan_s=None,
    )  # fmt: skip
    assert ep.cause == "background_starved"
    assert ep.detail.startswith("servo and RTI tasks left the background no processor time")
