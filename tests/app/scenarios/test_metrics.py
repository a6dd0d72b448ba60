"""Metrics and diagnosis computed from hand-built event logs (no controller core involved)."""

from __future__ import annotations

import pytest
from motionsim.app.scenarios.report import pmac_report, trio_report

from tests.app.scenarios.logbuilder import Feed


def stream_with_gap() -> Feed:
    """Three lines, the program runs dry at 3 ms, the host loads line 4 at 5 ms."""
    f = Feed()
    for n in (1, 2, 3):
        f.load(0.0, n, f"X{n}")
    f.at(0.0, "program", cs=1, state="running")
    for n in (1, 2, 3):
        t = (n - 1) * 0.001
        f.at(t, "line_calculated", cs=1, n=n).at(t, "move_start", cs=1, n=n)
        f.at(t + 0.001, "move_end", cs=1, n=n)
    f.at(0.003, "program", cs=1, state="waiting")
    f.load(0.005, 4, "X4")
    f.at(0.005, "program", cs=1, state="running")
    f.at(0.005, "line_calculated", cs=1, n=4).at(0.005, "move_start", cs=1, n=4)
    f.at(0.006, "move_end", cs=1, n=4)
    f.at(0.006, "program", cs=1, state="waiting")  # the end: nothing more to come
    return f


def test_waiting_with_lines_still_to_come_is_a_starvation():
    rep = pmac_report(stream_with_gap().events(), 0.010, i16=5)
    cs = rep["cs"][1]
    assert cs["starvations"] == 1
    assert cs["time_starved_s"] == pytest.approx(0.002)
    s = rep["starvation_list"][0]
    assert (s.start, s.end) == (pytest.approx(0.003), pytest.approx(0.005))


def test_waiting_after_the_last_line_is_not_a_starvation_unless_lines_were_unsent():
    events = stream_with_gap().events()
    assert pmac_report(events, 0.010)["cs"][1]["starvations"] == 1
    unsent = pmac_report(events, 0.010, total_lines={1: 9})["cs"][1]
    assert unsent["starvations"] == 2
    assert unsent["time_starved_s"] == pytest.approx(0.002 + 0.004)


def test_line_latency_is_loaded_to_move_start():
    cs = pmac_report(stream_with_gap().events(), 0.010)["cs"][1]
    assert cs["line_latency_max_s"] == pytest.approx(0.002)  # line 3: loaded 0, starts 2 ms
    assert cs["lines_executed"] == 4


def test_starvation_after_slow_poll_is_host_latency_with_coverage():
    f = Feed()
    for n in range(1, 7):
        f.load(0.0, n, f"X{n}")
    f.at(0.0, "program", cs=1, state="running")
    for n in range(1, 7):
        t = (n - 1) * 0.001
        f.at(t, "line_calculated", cs=1, n=n).at(t, "move_start", cs=1, n=n)
    f.at(0.006, "program", cs=1, state="waiting")
    f.load(0.010, 7, "X7")
    rep = pmac_report(f.events(), 0.02, i16=5)
    s = rep["starvation_list"][0]
    assert s.cause == "host_latency"
    # lines ahead fell below 5 (to 4) when line 2 was calculated at 1 ms
    assert s.facts["covered_s"] == pytest.approx(0.005)
    assert s.facts["host_response_s"] == pytest.approx(0.009)


def test_breq_edge_lost_in_the_service_routine_is_diagnosed_as_missed():
    f = Feed()
    f.at(0.0, "breq", cs=1, level=True)
    f.at(0.001, "host_irq", host="h", cs=1, missed=False, latency_s=0.001)
    f.load(0.001, 1, "X1").at(0.001, "breq", cs=1, level=False).at(0.001, "breq", cs=1, level=True)
    f.at(0.001, "host_write", host="h", cs=1, lines=1, sent=1, lines_ahead=1)
    f.at(0.001, "host_irq", host="h", cs=1, missed=True, latency_s=0.0)
    f.at(0.001, "program", cs=1, state="running")
    f.at(0.001, "line_calculated", cs=1, n=1).at(0.001, "move_start", cs=1, n=1)
    f.at(0.002, "program", cs=1, state="waiting")
    rep = pmac_report(f.events(), 0.1, total_lines={1: 100})
    s = rep["starvation_list"][0]
    assert s.cause == "breq_missed"
    assert s.length == pytest.approx(0.098)
    assert rep["cs"][1]["breq_missed"] == 1
    assert rep["cs"][1]["breq_rising"] == 2


def test_motion_stopped_at_a_dwell_is_a_lookahead_break():
    f = Feed()
    texts = ["X1", "DWELL 10", "X2"]
    for n, text in enumerate(texts, 1):
        f.load(0.0, n, text)
    f.at(0.0, "program", cs=1, state="running")
    f.at(0.0, "move_start", cs=1, n=1).at(0.001, "move_end", cs=1, n=1)
    f.at(0.001, "move_start", cs=1, n=2).at(0.011, "move_end", cs=1, n=2)
    f.at(0.0123, "move_start", cs=1, n=3).at(0.013, "move_end", cs=1, n=3)
    rep = pmac_report(f.events(), 0.02)
    (s,) = rep["starvation_list"]
    assert s.kind == "lookahead_break" and s.cause == "lookahead_dwell"
    assert (s.start, s.end) == (pytest.approx(0.011), pytest.approx(0.0123))
    assert rep["cs"][1]["time_starved_s"] == 0  # the buffer never ran dry


def test_rapid_mode_gap_is_a_lookahead_break():
    f = Feed()
    for n, text in enumerate(["RAPID X1", "X2", "LINEAR X3"], 1):
        f.load(0.0, n, text)
    f.at(0.0, "move_start", cs=1, n=1).at(0.002, "move_end", cs=1, n=1)
    f.at(0.003, "move_start", cs=1, n=2).at(0.004, "move_end", cs=1, n=2)
    f.at(0.004, "move_start", cs=1, n=3).at(0.005, "move_end", cs=1, n=3)
    (s,) = pmac_report(f.events(), 0.01)["starvation_list"]
    assert s.cause == "lookahead_rapid"


def test_mvar_lead_is_time_before_the_next_move_starts():
    f = Feed()
    for n, text in enumerate(["X10", "M1=1", "X20"], 1):
        f.load(0.0, n, text)
    f.at(0.0, "move_start", cs=1, n=1)
    f.at(0.0, "mvar", name="M1", value=1, sync=False)  # calculated ahead: at once
    f.at(0.5, "move_start", cs=1, n=3)
    (m,) = pmac_report(f.events(), 1.0)["cs"][1]["mvar"]
    assert m["next_move_line"] == 3
    assert m["lead_s"] == pytest.approx(0.5)


def test_tn20_axis_idle_while_process_blocked_on_other_axis():
    """TN20-16's table: axis 0 stops while the program waits at MOVE(VR(4)) AXIS(0), because
    the process buffer holds MOVE(VR(103)) for axis 1 until MOVE(VR(101)) finishes."""
    f = Feed()
    f.at(0.0, "axis", axis=0, mtype=1, ntype=1)
    f.at(0.0, "axis", axis=1, mtype=1, ntype=1)
    f.at(0.0, "process_buffer", process=1, axis=0, mtype=1)  # MOVE(VR(3))
    f.at(0.0, "process", process=1, state="blocked", line=3, blocked_on="MOVE(VR(103)) AXIS(1)")
    f.at(0.010, "axis", axis=0, mtype=1, ntype=1)  # VR(1) done: VR(2) up, VR(3) to NTYPE
    f.at(0.010, "process_buffer", process=1, axis=0, mtype=0)
    f.at(0.010, "process", process=1, state="running", line=3)
    f.at(0.010, "process_buffer", process=1, axis=1, mtype=1)  # MOVE(VR(103))
    f.at(0.010, "process", process=1, state="blocked", line=2, blocked_on="MOVE(VR(4)) AXIS(0)")
    f.at(0.020, "axis", axis=0, mtype=1, ntype=0)
    f.at(0.030, "axis", axis=0, mtype=0, ntype=0)  # "AXIS(0) has now stopped!"
    f.at(0.100, "axis", axis=1, mtype=1, ntype=1)  # VR(101) done
    f.at(0.100, "process_buffer", process=1, axis=1, mtype=0)
    f.at(0.100, "process", process=1, state="running", line=2)
    f.at(0.101, "axis", axis=0, mtype=1, ntype=0)  # VR(4) reaches axis 0 at last
    rep = trio_report(f.events(), 0.2)
    assert rep["axes"][0]["idle_while_blocked_s"] == pytest.approx(0.070)
    assert rep["axes"][1]["idle_while_blocked_s"] == 0
    (s,) = rep["starvation_list"]
    assert s.cause == "process_blocked_on_other_axis"
    assert (s.start, s.end) == (pytest.approx(0.030), pytest.approx(0.100))
    assert "process 1" in s.detail and "held a move for axis 1" in s.detail
    assert rep["axes"][0]["process_buffer_busy_s"] == pytest.approx(0.010)


def test_one_servo_period_hand_over_is_not_a_stall():
    f = Feed()
    f.at(0.0, "axis", axis=0, mtype=1, ntype=0)
    f.at(0.0, "process", process=1, state="blocked", line=2, blocked_on="MOVE(1) AXIS(1)")
    f.at(0.010, "axis", axis=0, mtype=0, ntype=0)
    f.at(0.011, "axis", axis=0, mtype=1, ntype=0)
    assert trio_report(f.events(), 0.1)["idle_while_blocked_s"] == 0


def test_a_run_time_error_is_an_episode_until_the_next_r_diagnosed_as_calculation_behind():
    """TUM p339: the controller aborted the program (``program`` event with ``error``)."""
    f = Feed()
    for n in range(1, 8):
        f.load(0.0, n, f"X{n}")
    f.at(0.0, "program", cs=1, state="running")
    for n in (1, 2, 3):
        t = (n - 1) * 0.001
        f.at(t, "line_calculated", cs=1, n=n).at(t, "move_start", cs=1, n=n)
    f.at(0.002, "program", cs=1, state="aborted", error="run_time_error")
    f.at(0.004, "move_end", cs=1, n=3)
    f.at(0.007, "program", cs=1, state="running")
    rep = pmac_report(f.events(), 0.010, i16=5, rti_period_s=0.00133)
    assert rep["cs"][1]["run_time_errors"] == 1
    assert rep["cs"][1]["starvations"] == 0  # not a buffer running dry
    (s,) = rep["starvation_list"]
    assert (s.kind, s.cause) == ("run_time_error", "calculation_fell_behind")
    assert (s.start, s.end) == (pytest.approx(0.002), pytest.approx(0.007))
    assert s.facts["move_s"] == pytest.approx(0.001)
    assert "calculation fell behind" in s.detail and "1.330 ms" in s.detail
