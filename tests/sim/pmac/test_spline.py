"""SPLINE1 / SPLINE2 move modes (TUM p290, p339; PUM p183; PUM-old p52; spec §11.2).

Each programmed point gives a way-point ``(P[i-1] + 4P[i] + P[i+1]) / 6`` and a velocity
``(P[i+1] - P[i-1]) / 2T`` at its segment boundary; each axis follows the cubic between
boundaries; a zero-distance segment of the same time is added at the start and at the end of
a series, so N points take (N + 2)·T. Times are asserted in servo cycles (events land on the
first servo cycle at or after the exact instant)."""

from __future__ import annotations

import math

import pytest
from motionsim.sim.pmac import PmacController


def _run(rig, lines, setup=()):
    rig.rotary_setup()
    for cmd in setup:
        rig.ok(cmd)
    rig.c.load_lines(1, lines)
    rig.ok("R")


def _cyc(rig, t):
    """The first servo cycle at or after ``t``."""
    return math.ceil(t / rig.period - 1e-6)


def _states(rig):
    return [f["state"] for _, _, f in rig.events("program")]


def test_tum_p290_n_points_take_n_plus_2_segment_times_with_the_added_pieces(rig):
    """4 points, T = 100 ms: the first line's move holds the added start segment (2T), the
    last line's the added end segment (2T), the others T; 6T from first motion to rest."""
    _run(rig, ["ABS SPLINE1 TM100 X10", "X20", "X40", "X40"])
    rig.run_until_idle()
    start, end = rig.by_n("move_start"), rig.by_n("move_end")
    t0 = start[1] * rig.period
    assert end[1] == start[2] == _cyc(rig, t0 + 0.2)
    assert end[2] == start[3] == _cyc(rig, t0 + 0.3)
    assert end[3] == start[4] == _cyc(rig, t0 + 0.4)
    assert end[4] == _cyc(rig, t0 + 0.6)
    assert _states(rig) == ["running", "waiting"]
    assert rig.c.positions(1) == {"X": pytest.approx(40.0)}


@pytest.mark.parametrize("tm", [50, 1000])
def test_tum_p290_a_single_point_is_three_segment_times(rig, tm):
    _run(rig, [f"ABS SPLINE1 TM{tm} X10"])
    rig.run_until_idle()
    start, end = rig.by_n("move_start"), rig.by_n("move_end")
    assert end[1] == _cyc(rig, start[1] * rig.period + 3 * tm / 1000)
    assert rig.c.positions(1)["X"] == pytest.approx(10.0)


def test_tum_p290_positions_at_segment_boundaries_are_the_way_points(rig):
    pts = [0.0, 10.0, 30.0, 20.0, 25.0]  # P0 = the rest position, then the programmed points
    _run(rig, ["ABS SPLINE1 TM100 X10 Y-5", "X30 Y-5", "X20 Y0", "X25 Y0"])
    rig.run_for(0.02)
    cs = rig.c.coord_system(1)
    b0, T = cs.current.b_start, 0.1
    pos = lambda t: rig.c.positions(1, t)  # noqa: E731
    vel = lambda t: cs._velocities(cs.current, t)  # noqa: E731
    assert pos(b0) == {"X": 0.0, "Y": 0.0} and vel(b0) == {"X": 0.0, "Y": 0.0}
    # boundary of the added start segment: P-1 = P0 = rest
    assert pos(b0 + T)["X"] == pytest.approx((5 * pts[0] + pts[1]) / 6)
    assert vel(b0 + T)["X"] == pytest.approx((pts[1] - pts[0]) / (2 * T))
    assert pos(b0 + T)["Y"] == pytest.approx(-5 / 6)
    # boundary i (end of line i's move): (P[i-1] + 4P[i] + P[i+1]) / 6, (P[i+1] - P[i-1]) / 2T
    for i in (1, 2, 3):
        t = b0 + (i + 1) * T
        if t > cs.current.b_end + 1e-12:
            rig.run_for(t - rig.c.env.now - 0.001)
        wp = (pts[i - 1] + 4 * pts[i] + pts[i + 1]) / 6
        assert pos(t)["X"] == pytest.approx(wp)
        assert vel(t)["X"] == pytest.approx((pts[i + 1] - pts[i - 1]) / (2 * T))


def test_pum_p183_the_way_point_differs_from_the_point_by_a_sixth_of_the_distance_change(rig):
    """Diff = (Dist[i+1] - Dist[i]) / 6 at the end of segment i (uniform spline)."""
    _run(rig, ["INC SPLINE1 TM100 X10", "X30", "X5", "X5"])
    rig.run_for(0.25)
    cs = rig.c.coord_system(1)
    m = cs.current
    assert m.n == 2
    # end of segment 2 (after P2 = 40): distances 30 then 5
    assert rig.c.positions(1, m.b_end)["X"] - 40.0 == pytest.approx((5 - 30) / 6)


def test_tum_p290_the_added_segments_accelerate_from_and_decelerate_to_rest(rig):
    _run(rig, ["ABS SPLINE1 TM100 X10", "X20"])
    rig.run_for(0.01)
    cs = rig.c.coord_system(1)
    b0 = cs.current.b_start
    eps = 1e-4
    assert cs._velocities(cs.current, b0)["X"] == pytest.approx(0.0)
    # S-curve start: acceleration starts at 0 as well (cubic from three equal points)
    assert cs._velocities(cs.current, b0 + eps)["X"] == pytest.approx(0.0, abs=1e-3)
    rig.run_for(0.3)
    m = cs.current
    assert m.n == 2
    assert cs._velocities(m, m.b_end)["X"] == pytest.approx(0.0)
    assert rig.c.positions(1, m.b_end)["X"] == pytest.approx(20.0)


def test_pum_old_p52_no_sudden_change_of_velocity_or_acceleration_at_boundaries(rig):
    _run(rig, ["ABS SPLINE1 TM80 X10", "X-5", "X30", "X0", "X0"])
    rig.run_for(0.005)
    cs = rig.c.coord_system(1)
    h = 1e-6
    seen = 0
    while cs.current is not None and cs.current.n < 5:
        m = cs.current
        if m.prev is not None:  # the boundary m.prev -> m
            b, p = m.b_start, m.prev
            assert cs._velocities(p, b)["X"] == pytest.approx(cs._velocities(m, b)["X"])
            a_left = (cs._velocities(p, b)["X"] - cs._velocities(p, b - h)["X"]) / h
            a_right = (cs._velocities(m, b + h)["X"] - cs._velocities(m, b)["X"]) / h
            assert a_left == pytest.approx(a_right, rel=1e-3)
            seen += 1
        rig.run_for(m.b_end - rig.c.env.now + 0.002)
    assert seen == 3


def test_tsrm_p286_cs_status_word2_mode_bits_spline_101(rig):
    _run(rig, ["ABS SPLINE2 TM100 X10"])
    rig.run_for(0.02)
    w1, w2 = int(rig.ok("??")[0:6], 16), int(rig.ok("??")[6:12], 16)
    assert (w2 >> 4 & 1, w2 >> 1 & 1, w2 & 1) == (1, 0, 1)
    assert w1 & (1 << 2)  # continuous motion: a blended (spline) move is executing


def test_tum_p290_spline2_segment_times_change_without_a_stop(rig):
    """SPLINE2 (non-uniform): T = 100, 100, 50, 50 ms; the series runs through: the lead-in
    has the first time, the end segment the last, and the velocity at the 100 -> 50 boundary
    is the [INF] weighted slope, not 0."""
    _run(rig, ["ABS SPLINE2 TM100 X10", "X20", "TM50 X30", "X30"])
    rig.run_until_idle()
    start, end = rig.by_n("move_start"), rig.by_n("move_end")
    t0 = start[1] * rig.period
    assert end[1] == start[2] == _cyc(rig, t0 + 0.2)
    assert end[2] == start[3] == _cyc(rig, t0 + 0.3)
    assert end[3] == start[4] == _cyc(rig, t0 + 0.35)
    assert end[4] == _cyc(rig, t0 + 0.45)
    assert _states(rig) == ["running", "waiting"]


def test_spline2_non_uniform_boundary_formulas(rig):
    """[INF] V = (s1·t2 + s2·t1) / (t1 + t2), WP = B + 2(s2 - s1)/(t1 + t2) · t1·t2 / 6."""
    _run(rig, ["ABS SPLINE2 TM100 X10", "TM50 X20", "X20"])
    rig.run_for(0.05)
    cs = rig.c.coord_system(1)
    m = cs.current
    t1, t2 = 0.1, 0.05
    s1, s2 = 10 / t1, 10 / t2
    assert cs._velocities(m, m.b_end)["X"] == pytest.approx((s1 * t2 + s2 * t1) / (t1 + t2))
    wp = 10 + 2 * (s2 - s1) / (t1 + t2) * t1 * t2 / 6
    assert rig.c.positions(1, m.b_end)["X"] == pytest.approx(wp)


def test_pum_p183_spline1_time_change_stops_and_restarts_the_series(rig):
    """SPLINE1: TM changes from 100 to 50 ms after 2 points: the first part comes to a stop
    (its end segment, 4T1 in all) and the rest starts from rest (3 points: 5T2)."""
    _run(rig, ["ABS SPLINE1 TM100 X10", "X20", "TM50 X30", "X40", "X50"])
    rig.run_until_idle()
    start, end = rig.by_n("move_start"), rig.by_n("move_end")
    t0 = start[1] * rig.period
    assert end[2] == start[3] == _cyc(rig, t0 + 0.4)
    assert end[5] == _cyc(rig, t0 + 0.4 + 0.25)
    cs_moves = rig.c.coord_system(1)
    assert cs_moves.current is None and rig.c.positions(1)["X"] == pytest.approx(50.0)


def test_spline1_time_change_passes_through_rest_at_the_last_point(rig):
    _run(rig, ["ABS SPLINE1 TM100 X10", "X20", "TM50 X30", "X40"])
    rig.run_for(0.35)
    cs = rig.c.coord_system(1)
    m = cs.current
    assert m.n == 2
    assert cs._velocities(m, m.b_end)["X"] == pytest.approx(0.0)
    assert rig.c.positions(1, m.b_end)["X"] == pytest.approx(20.0)


def test_tum_p339_spline_reads_one_line_further_ahead_than_linear(make_rig):
    """A spline move needs the next point: with the same 2-moves-ahead depth, calculation
    from rest works through 4 lines (3 moves + the waiting point) where LINEAR takes 3 — PR
    reports one line fewer."""
    ahead = {}
    for mode in ("LINEAR", "SPLINE1"):
        rig = make_rig()
        _run(rig, [f"ABS {mode} TM100 X1"] + [f"X{i}" for i in range(2, 10)])
        rig.run_for(0.01)
        ahead[mode] = int(rig.ok("PR"))
        assert len(rig.by_n("line_calculated")) == 9 - ahead[mode]
    assert ahead == {"LINEAR": 6, "SPLINE1": 5}


def test_tum_p339_after_each_move_start_planning_keeps_two_moves_and_the_next_point(rig):
    _run(rig, ["ABS SPLINE1 TM20"] + [f"X{i}" for i in range(1, 16)])
    rig.run_for(0.15)
    start, calc = rig.by_n("move_start"), rig.by_n("line_calculated")
    r = int(rig.c.vars.I(8)) + 1
    for n in (5, 6, 7):  # move n executing: moves n+1, n+2 calculated, point n+3 read
        assert calc[n + 3] == (start[n] // r + 1) * r
        assert calc[n + 3] > start[n - 1]


def test_tum_p339_a_host_streaming_spline_points_under_breq_is_asked_one_line_earlier():
    """A host loading one point per BREQ (I16 = 5, I17 = 10): every line runs without error,
    the series takes (N + 2)·T, and after each move start calculation has reached one line
    further than with LINEAR — so the buffer drains (PR, BREQ) one line earlier per move."""
    reach = {}
    for mode in ("LINEAR", "SPLINE1"):
        c = PmacController("s")
        c.define_rotary(1, 600)
        c.load_lines(1, [f"ABS {mode} TA10 TS0 TM20"])
        c.run(1)
        rot = c.coord_system(1).rotary
        n = 60

        def host(c=c, rot=rot, n=n):
            for i in range(n):
                if not rot.breq:
                    yield c.wait_breq(1)
                c.load_lines(1, [f"X{i}"])

        c.env.process(host())
        c.env.run(until=5.0)
        starts = {e["n"]: e.t for e in c.log.events("move_start")}
        ends = {e["n"]: e.t for e in c.log.events("move_end")}
        assert sorted(starts) == sorted(ends) == list(range(2, n + 2))  # line 1: the header
        assert [e["state"] for e in c.log.events("program")] == ["running", "waiting"]
        assert rot.used_words == 0 and rot.lines_ahead == 0  # every line's words given back
        calc = [(e.t, e["n"]) for e in c.log.events("line_calculated")]
        rti = 3.5 * c.scheduler.period_s  # the next RTI, strictly after the start
        reach[mode] = {
            k: max(m for t, m in calc if t <= starts[k] + rti) - k for k in range(10, 50)
        }
        if mode == "SPLINE1":
            total = ends[n + 1] - starts[2]
            assert total == pytest.approx((n + 2) * 0.020, abs=c.scheduler.period_s)
    assert set(reach["LINEAR"].values()) == {2}
    assert set(reach["SPLINE1"].values()) == {3}


@pytest.mark.parametrize("tm", ["0", "-5", "5000"])
def test_spline_segment_time_out_of_range_is_a_run_time_error_nothing_moves(rig, tm):
    """The move-time register holds (0, 4095.9998] ms (TUM p292); a spline line calculated
    with a time outside it aborts the CS with a run-time error [INF]."""
    _run(rig, [f"ABS SPLINE1 TM{tm} X10", "X20"])
    rig.run_until_idle()
    progs = [f for _, _, f in rig.events("program")]
    assert progs[-1] == {"cs": 1, "state": "aborted", "error": "run_time_error"}
    assert rig.events("move_start") == []
    assert int(rig.ok("??")[6:12], 16) & (1 << 22)


@pytest.mark.parametrize(
    "line, column",
    [("SPLINE X1", 8), ("SPLINE3 X1", 7), ("SPLINE1.5 X1", 7), ("SPLINE1 X10:5", 12),
     ("SPLINE2 X", 9)],
)  # fmt: skip
def test_bad_spline_lines_are_err003_with_the_column_and_nothing_is_stored(rig, line, column):
    rig.assert_refused_err003(line, column)


def test_a_velocity_word_calculated_in_spline_mode_is_a_run_time_error(rig):
    _run(rig, ["ABS SPLINE1 TM100", "X10:5"])
    rig.run_until_idle()
    assert [f for _, _, f in rig.events("program")][-1]["error"] == "run_time_error"


def test_a_spline_line_costs_one_word_per_command_word(rig):
    rig.rotary_setup()
    rig.c.load_lines(1, ["SPLINE1 X10 Y3", "X10 Y3"])
    assert [f["words"] for _, _, f in rig.events("line_loaded")] == [3, 2]


def test_spline_is_no_longer_refused_as_not_simulated(rig):
    port = rig.c.open_port("host")
    rig.rotary_setup()
    rig.ok("OPEN ROT", port)
    assert rig.cmd("SPLINE1 X10", port).error is None


def test_a_linear_move_ends_the_series_at_rest_before_it_starts(rig):
    _run(rig, ["ABS SPLINE1 TM100 X10", "X20", "LINEAR TA10 TS0 TM100 X0"])
    rig.run_until_idle()
    start, end = rig.by_n("move_start"), rig.by_n("move_end")
    t0 = start[1] * rig.period
    assert end[2] == _cyc(rig, t0 + 0.4)  # 2 points: (2 + 2)·T
    assert start[3] == end[2]
    assert rig.c.positions(1)["X"] == pytest.approx(0.0)


def test_tsrm_p429_a_dwell_ends_the_series_and_holds_at_the_last_point(rig):
    _run(rig, ["ABS SPLINE1 TM100 X10", "X20", "DWELL50", "X30"])
    rig.run_for(0.42)
    assert rig.c.coord_system(1).current.n == 3  # the dwell
    assert rig.c.positions(1)["X"] == pytest.approx(20.0)
    rig.run_until_idle()
    start, end = rig.by_n("move_start"), rig.by_n("move_end")
    t0 = start[1] * rig.period
    assert end[2] == start[3] == _cyc(rig, t0 + 0.4)
    assert end[4] == _cyc(rig, start[4] * rig.period + 0.3)  # a new single-point series: 3T


def test_spec_11_2_ixx16_does_not_limit_a_spline(rig):
    """#1 -> 1000X with I116 = 0.01 cts/ms (10 units/s at 1000 cts/unit): the spline keeps its
    (N + 2)·T although it needs far more."""
    _run(rig, ["ABS SPLINE1 TM100 X10", "X20"], setup=["&1 #1->1000X", "I116=0.01"])
    rig.run_until_idle()
    start, end = rig.by_n("move_start"), rig.by_n("move_end")
    assert end[2] == _cyc(rig, start[1] * rig.period + 0.4)


def test_a_synchronous_write_lands_at_the_start_of_its_lines_spline_move(rig):
    _run(rig, ["ABS SPLINE1 TM100 X10", "M1==1 X20", "X30"])
    rig.run_until_idle()
    start = rig.by_n("move_start")
    writes = [k for k, _, f in rig.events("mvar") if f["sync"]]
    # TUM p250: at the first RTI (every I8+1 = 3 cycles) at or after that move's start
    assert writes == [-(-start[2] // 3) * 3]


def test_feedrate_override_stretches_the_spline(rig):
    _run(rig, ["ABS SPLINE1 TM100 X10", "X20"], setup=["I5194=8388607", "%50"])
    rig.run_until_idle()
    start, end = rig.by_n("move_start"), rig.by_n("move_end")
    assert end[2] == _cyc(rig, start[1] * rig.period + 0.8)


def test_quit_during_a_series_runs_the_waiting_point_to_rest(rig):
    _run(rig, ["ABS SPLINE1 TM100 X10", "X20", "X30", "X40", "X50", "X60"])
    rig.run_for(0.05)
    rig.ok("Q")
    rig.run_until_idle()
    end = rig.by_n("move_end")
    assert _states(rig)[-1] == "stopped"
    last = max(end)
    assert rig.c.positions(1)["X"] == pytest.approx(10.0 * last)
    rig.ok("R")  # the rest of the lines run as a new series from there
    rig.run_until_idle()
    assert _states(rig)[-1] == "waiting"
    assert rig.c.positions(1)["X"] == pytest.approx(60.0)
    assert rig.c.rotary(1)["used_words"] == 0


def test_abort_during_a_spline_decelerates_from_its_velocity(rig):
    _run(rig, ["ABS SPLINE1 TM100 X10", "X20", "X30", "X40"])
    rig.run_for(0.2)
    cs = rig.c.coord_system(1)
    v = cs._velocities(cs.current, rig.c.env.now)["X"]
    assert v > 0
    rig.ok("A")
    rig.run_until_idle()
    assert _states(rig)[-1] == "aborted"
    assert cs.spline is None and not cs.planned


def test_tum_p339_spline_segments_shorter_than_the_rti_can_follow_abort_with_a_run_time_error(
    make_rig,
):
    """0.5 ms segments with I8 = 2 (RTI every 1.33 ms): two moves ahead cover 1 ms, planning
    falls behind; with I8 = 0 (an RTI every servo cycle) the same stream runs."""
    for i8, last in ((2, {"cs": 1, "state": "aborted", "error": "run_time_error"}),
                     (0, {"cs": 1, "state": "waiting"})):  # fmt: skip
        rig = make_rig()
        _run(rig, ["ABS SPLINE1 TM0.5"] + [f"X{i}" for i in range(1, 40)], setup=[f"I8={i8}"])
        rig.run_until_idle()
        assert [f for _, _, f in rig.events("program")][-1] == last
    assert len(rig.by_n("move_end")) == 39


def test_tsrm_p381_a_fixed_programs_spline_series_ends_with_the_program(rig):
    """B{n} R: the last point of the program ends the series (its end segment to rest), then
    the program is stopped (TSRM p381)."""
    for cmd in ("OPEN PROG 5", "CLEAR", "ABS SPLINE1 TM50", "X10", "X20", "X30", "CLOSE",
                "&1 B5 R"):  # fmt: skip
        rig.ok(cmd)
    rig.run_until_idle()
    start, end = rig.by_n("move_start"), rig.by_n("move_end")
    assert sorted(end) == [2, 3, 4]
    assert end[4] == _cyc(rig, start[2] * rig.period + 0.25)  # (3 + 2) x 50 ms
    assert _states(rig) == ["running", "stopped"]
    assert rig.c.positions(1)["X"] == pytest.approx(30.0)


def test_single_step_runs_one_spline_move_and_stops_at_its_boundary(rig):
    """[INF] S: one line's move (here the first: added segment + its own), stopped at its end
    way-point; R then runs the rest of the series to the last point."""
    rig.rotary_setup()
    rig.c.load_lines(1, ["ABS SPLINE1 TM50", "X10", "X20", "X30"])
    rig.ok("S")
    rig.run_until_idle()
    start, end = rig.by_n("move_start"), rig.by_n("move_end")
    assert sorted(end) == [2] and end[2] == _cyc(rig, start[2] * rig.period + 0.1)
    assert rig.c.positions(1)["X"] == pytest.approx((0 + 4 * 10 + 20) / 6)
    assert _states(rig) == ["running", "stopped"]
    rig.ok("R")
    rig.run_until_idle()
    assert rig.c.positions(1)["X"] == pytest.approx(30.0)
    assert _states(rig)[-1] == "waiting"
