"""PVT move mode (TSRM p463, p406; TUM p292, p339; PUM p180; spec §11.1).

``PVT{t}`` sets the segment time; ``X{pos}:{vel}`` the end position and signed end velocity
(user units per Isx90 ms); each axis follows the cubic joining start and end position and
velocity; segments abut, so N segments take exactly the sum of their times. Times are asserted
in servo cycles (events land on the first servo cycle at or after the exact instant)."""

from __future__ import annotations

import math

import pytest


def _run(rig, lines, **kw):
    rig.rotary_setup()
    for cmd in kw.get("setup", ()):
        rig.ok(cmd)
    rig.c.load_lines(1, lines)
    rig.ok("R")


def _cyc_at_or_after(rig, t):
    return math.ceil(t / rig.period - 1e-6)


def test_tsrm_p463_pvt_segments_abut_and_take_exactly_the_sum_of_their_times(rig):
    _run(rig, ["ABS PVT100 X10:100", "X20:100", "PVT50 X25:0", "DWELL0"])
    rig.run_until_idle()
    start, end = rig.by_n("move_start"), rig.by_n("move_end")
    t0 = start[1] * rig.period
    assert end[1] == start[2] == _cyc_at_or_after(rig, t0 + 0.1)
    assert end[2] == start[3] == _cyc_at_or_after(rig, t0 + 0.2)
    assert end[3] == _cyc_at_or_after(rig, t0 + 0.25)


def test_tsrm_p463_each_axis_follows_the_hermite_cubic_through_position_and_velocity(rig):
    _run(rig, ["ABS PVT200 X10:100 Y-4:-20", "X30:0 Y0:0"])
    rig.run_for(0.05)
    cs = rig.c.coord_system(1)
    m = cs.current
    b0, T = m.b_start, 0.2
    for frac in (0.0, 0.25, 0.5, 0.9):
        t = b0 + frac * T
        # p(t) = p0 + v0 t + a t^2 + b t^3 with Δ = p1 - p0 (spec §11.1)
        for axis, p1, v1 in (("X", 10.0, 100.0), ("Y", -4.0, -20.0)):
            a = (3 * p1 - 2 * 0 * T - v1 * T) / T**2
            b = (v1 * T - 2 * p1) / T**3
            tau = frac * T
            assert rig.c.positions(1, t)[axis] == pytest.approx(a * tau**2 + b * tau**3)
    assert rig.c.positions(1, b0 + T)["X"] == pytest.approx(10.0)
    rig.run_for(0.2)
    m2 = cs.current
    assert m2.n == 2 and m2.b_start == pytest.approx(b0 + T)
    v = cs._velocities(m2, m2.b_start)
    assert v["X"] == pytest.approx(100.0) and v["Y"] == pytest.approx(-20.0)


def test_tsrm_p406_no_velocity_means_end_velocity_zero(rig):
    _run(rig, ["ABS PVT100 X10", "X20:50"])
    rig.run_for(0.05)
    cs = rig.c.coord_system(1)
    m = cs.current
    assert cs._velocities(m, m.b_end)["X"] == pytest.approx(0.0, abs=1e-9)


def test_tsrm_p406_velocity_is_in_user_units_per_isx90_ms(rig):
    """Isx90 = 1 ms: ``X10:0.1`` is 0.1 units per ms = 100 units/s."""
    _run(rig, ["ABS PVT100 X10:0.1", "X20:0"], setup=["I5190=1"])
    rig.run_for(0.05)
    cs = rig.c.coord_system(1)
    m = cs.current
    assert cs._velocities(m, m.b_end)["X"] == pytest.approx(100.0)


def test_tum_p339_pvt_is_calculated_one_move_ahead(rig):
    """Each segment start asks for the next; planning at the next RTI calculates one."""
    _run(rig, ["ABS PVT20"] + [f"X{i}:10" for i in range(1, 11)])
    rig.run_for(0.1)
    start, calc = rig.by_n("move_start"), rig.by_n("line_calculated")
    r = int(rig.c.vars.I(8)) + 1
    for n in (4, 5, 6):  # line n holds a segment; line n+1 the next one
        assert calc[n + 1] == (start[n] // r + 1) * r
        assert calc[n + 1] > start[n - 1]  # not calculated earlier: one move ahead
    assert rig.c.rotary(1)["lines_ahead"] > 0


def test_tum_p339_pvt_segments_shorter_than_the_rti_period_abort_with_a_run_time_error(rig):
    """1 ms segments with I8 = 2 (RTI every 1.33 ms): one segment ahead cannot keep up."""
    _run(rig, ["ABS PVT1"] + [f"X{i}:1" for i in range(1, 30)])
    rig.run_for(0.1)
    progs = [f for _, _, f in rig.events("program")]
    assert progs[-1] == {"cs": 1, "state": "aborted", "error": "run_time_error"}
    assert int(rig.ok("??")[6:12], 16) & (1 << 22)


def test_pvt_5ms_segments_stream_with_i8_0_without_error(make_rig):
    rig = make_rig()
    _run(rig, ["ABS PVT5"] + [f"X{i}:200" for i in range(1, 40)], setup=["I8=0"])
    rig.run_until_idle()
    assert all("error" not in f for _, _, f in rig.events("program"))
    assert len(rig.by_n("move_end")) == 39


def test_spec_11_1_a_sequence_ending_with_velocity_stops_at_the_end_point(rig):
    """[INF] run-out after a segment with v1 != 0: the axes stop at its end point."""
    _run(rig, ["ABS PVT100 X10:100"])
    rig.run_until_idle()
    end = rig.by_n("move_end")[1]
    assert end == _cyc_at_or_after(rig, rig.by_n("move_start")[1] * rig.period + 0.1)
    assert rig.c.positions(1) == {"X": pytest.approx(10.0)}
    assert [f["state"] for _, _, f in rig.events("program")] == ["running", "waiting"]


def test_tsrm_p286_cs_status_word2_mode_bits_pvt_110(rig):
    _run(rig, ["ABS PVT100 X10:0"])
    rig.run_for(0.02)
    w2 = int(rig.ok("??")[6:12], 16)
    assert (w2 >> 4 & 1, w2 >> 1 & 1, w2 & 1) == (1, 1, 0)


def test_tsrm_p429_feedrate_override_stretches_a_pvt_segment(rig):
    _run(rig, ["ABS PVT100 X10:0"], setup=["I5194=8388607", "%50"])
    rig.run_until_idle()
    start, end = rig.by_n("move_start")[1], rig.by_n("move_end")[1]
    assert end == _cyc_at_or_after(rig, start * rig.period + 0.2)


def test_inc_pvt_words_are_distances(rig):
    _run(rig, ["INC PVT50 X5:0", "X5:0", "X5:0"])
    rig.run_until_idle()
    assert rig.c.positions(1)["X"] == pytest.approx(15.0)


def test_a_pvt_axis_word_takes_two_words(rig):
    rig.rotary_setup()
    rig.c.load_lines(1, ["X10:5 Y3:1", "X10 Y3"])
    words = [f["words"] for _, _, f in rig.events("line_loaded")]
    assert words == [4, 2]


@pytest.mark.parametrize(
    "line, column",
    [("PVT0 X1:0", 4), ("PVT-5 X1:0", 4), ("PVT5000 X1:0", 4), ("PVT X1", 5), ("X10:", 5),
     ("PVT100 X10:Y2", 12)],
)  # fmt: skip
def test_bad_pvt_lines_are_err003_with_the_column_and_nothing_is_stored(rig, line, column):
    rig.assert_refused_err003(line, column)


def test_a_pvt_time_expression_out_of_range_at_calculation_is_a_run_time_error(rig):
    _run(rig, ["P1=0", "ABS PVT(P1) X1:0", "X2:0"])
    rig.run_until_idle()
    progs = [f for _, _, f in rig.events("program")]
    assert progs[-1] == {"cs": 1, "state": "aborted", "error": "run_time_error"}
    assert rig.by_n("move_start") == {}



@pytest.mark.parametrize("isx89", ["5000", "0"])
@pytest.mark.parametrize("lines", [["X20:0"], ["X20"], ["P1=1", "X20:0"]])
def test_a_segment_time_made_out_of_range_on_line_is_a_run_time_error_at_the_next_segment(
    rig, isx89, lines
):
    """The PVT segment time is Isx89 (TSRM p463, up to 4095.9998 ms): set out of range on-line
    while the program waits for lines, the next streamed segment cannot be calculated — a
    run-time error, as the same value programmed (above) — not a segment of no time. Also
    for a segment without a velocity word, and after a line without a move (``P1=1``)."""
    _run(rig, ["ABS PVT100 X10:0"])
    rig.run_until_idle()
    assert rig.c.coord(1)["program"]["state"] == "waiting"
    rig.ok(f"I5189={isx89}")
    rig.c.load_lines(1, lines)
    rig.run_until_idle()
    progs = [f for _, _, f in rig.events("program")]
    assert progs[-1] == {"cs": 1, "state": "aborted", "error": "run_time_error"}
    assert list(rig.by_n("move_start")) == [1]
    assert rig.c.positions(1) == {"X": 10.0}
