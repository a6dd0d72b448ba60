"""Edges of move execution pinned to the manual: the blend-ramp clip and the hand-off in
segmentation mode (spec §9.1-9.2), a spline series after a LINEAR move (TUM p290), the
synchronous write of an unsegmented move with Isx13 > 0 (TUM p250), and the motor velocity
in the servo cycle ``%0`` freezes the time base (TSRM p191). Times are servo cycles.
"""

from __future__ import annotations

import math

import pytest


def _start(rig, lines: list[str], *setup: str) -> None:
    rig.rotary_setup()
    for s in setup:
        rig.ok(s)
    rig.c.load_lines(1, lines)
    rig.ok("R")


def _cycles(rig, ms: float) -> int:
    """Whole servo cycles up to the first at or after ``ms``."""
    return math.ceil(rig.ms_cycles(ms) - 1e-6)


def _states(rig) -> list[str]:
    return [f["state"] for _, _, f in rig.events("program")]


# -- blending in segmentation mode (Isx13 > 0) ------------------------------------------------


def test_segmentation_mode_clips_the_next_ta_to_twice_tm_less_half_ta_at_the_blend_centre(
    make_rig,
):
    """Spec §9.1 (Quick Ref p49): TA(i+1) ≤ 2·(TM(i) − TA(i)/2), with Isx13 > 0 too. Move 1
    (TM100, TA20 from rest, 100 units/s) allows 180 ms; ``TA190`` is clipped to it. The blend
    from 100 to 50 units/s is a constant acceleration centred on the programmed point X10, so
    the axis passes that instant Δv·Ta/8 = 50 · 0.18 / 8 short of it."""
    rig = make_rig(i5113=10)
    _start(rig, ["TM100 TA20 TS0 X10", "TM200 TA190 X20"])
    rig.run_for(0.01)
    t_corner = rig.by_n("move_start")[1] * rig.period + 0.010 + 0.100  # Ta/2 + TM
    rig.c.env.run(until=t_corner + 0.001)
    assert rig.c.coord(1)["program"]["line"] == 2
    assert rig.c.positions(1, t_corner)["X"] == pytest.approx(10.0 - 50 * 0.180 / 8)


def test_segmentation_mode_a_next_move_streamed_during_the_first_still_blends_centred(make_rig):
    """As above, but ``TM200 TA190 X20`` is sent 5 ms into the first move (calculated at the
    next RTI, before its 180-ms ramp must begin): the blend is the same, centred on X10."""
    rig = make_rig(i5113=10)
    _start(rig, ["TM100 TA20 TS0 X10"])
    rig.run_for(0.005)
    rig.c.load_lines(1, ["TM200 TA190 X20"])
    t_corner = rig.by_n("move_start")[1] * rig.period + 0.010 + 0.100  # Ta/2 + TM
    rig.c.env.run(until=t_corner + 0.001)
    assert rig.c.positions(1, t_corner)["X"] == pytest.approx(10.0 - 50 * 0.180 / 8)


def test_segmentation_mode_a_shorter_next_ta_starts_its_blend_half_that_ta_before_the_point(
    make_rig,
):
    """Spec §9.1-9.2: with Isx13 > 0 the blend into a calculated next move is centred on the
    programmed point with the next move's TA. Move 1 (TM500 TA100) passes X10 at 50 + 500 ms;
    ``TA20`` makes move 2 start 10 ms before that, 540 ms after move 1 starts."""
    rig = make_rig(i5113=10)
    _start(rig, ["TM500 TA100 TS0 X10", "TA20 X20"])
    rig.run_until_idle()
    starts = rig.by_n("move_start")
    assert starts[2] - starts[1] == _cycles(rig, 540)
    assert rig.by_n("move_end")[1] == starts[2]


# -- a spline series after a LINEAR move ---------------------------------------------------


def test_a_spline_point_after_a_linear_move_runs_from_rest_in_three_segment_times(rig):
    """TUM p290: a series gets a zero-distance segment at each end, so N points take
    (N + 2)·T. A single ``SPLINE1 TM100`` point after a LINEAR move (which stops first: TM +
    TA) starts when that move has stopped and runs 300 ms to X2; then the program waits."""
    _start(rig, ["TM100 TA10 TS0 X1", "SPLINE1 TM100 X2"])
    rig.run_until_idle()
    starts, ends = rig.by_n("move_start"), rig.by_n("move_end")
    assert ends[1] - starts[1] == _cycles(rig, 110)
    assert starts[2] == ends[1]
    assert ends[2] == math.ceil((starts[2] * rig.period + 0.3) / rig.period - 1e-6)
    assert _states(rig) == ["running", "waiting"]
    assert rig.c.positions(1) == {"X": pytest.approx(2.0)}


def test_a_spline_point_arriving_as_the_linear_move_stops_joins_the_waiting_point_series(rig):
    """TUM p290, p339: a spline point needs the next one; ``X3`` arrives in the last servo
    cycle of the LINEAR move's stop, before any RTI could calculate it. It is calculated at
    the next RTI and continues the series of the waiting point X2: one series of two points,
    (2 + 2)·T = 400 ms, not two single-point series of 3·T each."""
    _start(rig, ["TM100 TA10 TS0 X1", "SPLINE1 TM100 X2"])
    rig.run_for(0.01)
    k_stop = rig.by_n("move_start")[1] + _cycles(rig, 110)
    rig.c.env.run(until=(k_stop - 1) * rig.period)
    rig.c.load_lines(1, ["X3"])
    rig.run_until_idle()
    starts, ends = rig.by_n("move_start"), rig.by_n("move_end")
    assert ends[1] == k_stop
    t2 = starts[2] * rig.period
    assert ends[2] == starts[3] == math.ceil((t2 + 0.2) / rig.period - 1e-6)
    assert ends[3] == math.ceil((t2 + 0.4) / rig.period - 1e-6)
    assert rig.c.positions(1) == {"X": pytest.approx(3.0)}


# -- synchronous writes with Isx13 > 0 -----------------------------------------------------------


def test_segmentation_mode_a_pvt_moves_synchronous_write_waits_only_for_the_rti(make_rig):
    """TUM p250: the queue is served at RTIs (every I8+1 = 3 cycles). With Isx13 > 0 only
    LINEAR / CIRCLE / DELAY are cut into Isx13 segments ``[INF]``; a PVT move's write lands at
    the first RTI at or after its start (15 ms segments: not the 20 ms segment boundary)."""
    rig = make_rig(i5113=10)
    _start(rig, ["ABS PVT15 X1:100", "M1==1 X2:100", "X3:0"])
    rig.run_until_idle()
    k2 = rig.by_n("move_start")[2]
    writes = [k for k, _, f in rig.events("mvar") if f["sync"]]
    assert writes == [-(-k2 // 3) * 3]


# -- %0: the time base freezes --------------------------------------------------------------


def test_v_on_the_line_of_percent_zero_reports_the_velocity_of_the_last_servo_cycle(rig):
    """``V`` is the motor velocity in counts per servo cycle over the last cycle; ``%0``
    (TSRM p191, instant at Isx94 = 8388607) freezes the commanded position from its own servo
    cycle on. ``#1V`` on the ``%0`` line still reports the cruise (100 units/s at 1000
    counts/unit), ``#1V`` a cycle later reports 0."""
    rig.ok("&1 #1->1000X")
    _start(rig, ["TM1000 TA100 TS0 X100"], "I116=1000", "I117=10", "I5194=8388607")
    rig.run_for(0.5)
    v = rig.cmd("%0 #1V")
    assert float(v.reply) == pytest.approx(100 * 1000 * rig.period, abs=1e-3)
    after = rig.cmd("#1V")
    assert rig.cyc(after.t_done) > rig.cyc(v.t_done)
    assert float(after.reply) == 0.0


@pytest.mark.parametrize("pct", [0, 1])
def test_a_dwell_ends_on_time_under_any_feed_override_and_the_next_move_waits_only_at_0(
    rig, pct
):
    """TSRM p191: DWELL does not use the time base, moves do. ``%{pct}`` typed during a
    2-s DWELL: the DWELL still ends 2 s after it began. At ``%1`` the next move starts then
    (slowly), calculated at the first RTI after the DWELL break (every 3rd cycle); at ``%0``
    the time base is frozen and it starts only when ``%100`` is typed."""
    _start(rig, ["TM100 TA10 TS0 X1", "DWELL2000", "X2"])
    rig.run_for(0.3)
    rig.ok(f"%{pct}")
    rig.run_for(2.5)
    dwell_end = rig.by_n("move_end")[2]
    assert dwell_end - rig.by_n("move_start")[2] == _cycles(rig, 2000)
    starts = rig.by_n("move_start")
    if pct:
        assert starts[3] == (dwell_end // 3 + 1) * 3
        rig.run_until_idle(30.0)  # X2, calculated at %1, takes 100 x (100 + 10) ms
        assert rig.by_n("move_end")[3] - starts[3] == _cycles(rig, 100 * 110)
        return
    assert 3 not in starts
    rig.ok("%100")
    k_raise = rig.cyc(rig.c.now)
    rig.run_until_idle()
    assert rig.by_n("move_start")[3] >= k_raise
    assert rig.c.positions(1) == {"X": pytest.approx(2.0)}


def test_at_1_percent_a_move_ending_in_a_stop_goes_on_to_the_calculated_dwell(rig):
    """``%1`` stretches the time base 100-fold (TSRM p191) but does not stop it: the move
    before a DWELL still comes to its stop, and the DWELL calculated with it (a break is
    calculated itself, TUM p341) starts then, at that move's end cycle, ~190 s later."""
    _start(rig, ["TM2000 TA10 TS0 X1", "DWELL10", "X2"])
    rig.run_for(0.05)
    rig.ok("%1")  # reached after the Isx94 slew, long before the move's end
    rig.run_until_idle(400.0)
    assert rig.by_n("move_start")[2] == rig.by_n("move_end")[1]
    assert rig.c.positions(1) == {"X": pytest.approx(2.0)}


@pytest.mark.parametrize("late_s", [None, 0.05])
def test_segmentation_mode_a_longer_next_ta_never_sends_the_axis_back(make_rig, late_s):
    """Isx13 = 10: the blend of ``TM100 TA20 X10`` into ``TM200 TA190 X20`` is clipped to
    180 ms (above) and centred on X10, so it begins 80 ms before the first move's own
    deceleration point: calculated one move ahead, the blend is decided there. Streamed
    50 ms into the first move, after that instant, the ramp starts at once, shortened to the
    time left ``[INF]``. Either way the commanded path is continuous — X never moves
    backwards, never faster than the 100 units/s of the first move — and ends at 20."""
    rig = make_rig(i5113=10)
    lines = ["TM100 TA20 TS0 X10", "TM200 TA190 X20"]
    _start(rig, lines if late_s is None else lines[:1])
    if late_s is not None:
        rig.run_for(late_s)
        rig.c.load_lines(1, lines[1:])
    xs = []
    for _ in range(1400):  # every servo cycle for 0.62 s
        rig.c.env.run(until=rig.c.env.now + rig.period)
        xs.append(rig.c.positions(1).get("X", 0.0))
    steps = [b - a for a, b in zip(xs, xs[1:], strict=False)]
    assert min(steps) >= 0
    assert max(steps) <= 100 * rig.period * (1 + 1e-6)
    assert rig.by_n("move_start")[2] == rig.by_n("move_end")[1]
    assert xs[-1] == pytest.approx(20.0)
