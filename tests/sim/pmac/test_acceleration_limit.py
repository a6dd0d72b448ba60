"""Ixx17 maximum program acceleration for non-segmented LINEAR moves (PSRM p74-75 Ix17; TUM
p276 "Mode 1" and "When Too Effective"; spec §11.3). X is motor 1, Y motor 2, at 1000 counts
per unit unless said otherwise; Ixx16 is raised so only Ixx17 acts. Times in servo cycles.

A move from rest of time T with ramp Ta takes T + Ta from ``move_start`` to ``move_end`` (half
a ramp up, T, half a ramp down, spec §9.1).
"""

from __future__ import annotations

import math

import pytest


def _setup(rig, *cmds, scale=1000):
    rig.rotary_setup()
    rig.ok(f"&1 #1->{scale}X")
    rig.ok(f"&1 #2->{scale}Y")
    rig.ok("I116=100000")
    rig.ok("I216=100000")
    for c in cmds:
        rig.ok(c)


def _run(rig, lines):
    rig.c.load_lines(1, lines)
    rig.ok("R")
    rig.run_until_idle()


def _cycles(rig, s):
    return math.ceil(s / rig.period - 1e-6)


def _span(rig, n):
    """Cycles from line ``n``'s ``move_start`` to its ``move_end``."""
    return rig.by_n("move_end")[n] - rig.by_n("move_start")[n]


def test_psrm_p74_a_ramp_over_ixx17_is_stretched_for_all_motors_same_path(rig):
    """TM1000 TA100 X10 Y5: X asks 10 counts/ms in 100 ms = 0.1 counts/ms²; Ixx17 = 0.05
    doubles TA to 200 ms (the move keeps its 1000 ms), for Y too, whose own limit is high."""
    _setup(rig, "I117=0.05", "I217=1000")
    rig.c.load_lines(1, ["LINEAR ABS TA100 TS0 TM1000 X10 Y5"])
    rig.ok("R")
    rig.run_for(0.15)  # inside the stretched ramp (the unstretched one ends at 100 ms)
    pos = rig.c.positions(1)
    assert 0 < pos["X"] < 1 and pos["Y"] == pytest.approx(pos["X"] / 2)  # same straight path
    m = rig.c.coord_system(1).current
    assert m.ta == pytest.approx(0.200)
    rig.run_until_idle()
    assert _span(rig, 1) == _cycles(rig, 1.200)


def test_psrm_p74_ixx17_above_the_programmed_acceleration_changes_nothing(rig):
    _setup(rig, "I117=0.2", "I217=0.2")
    _run(rig, ["LINEAR ABS TA100 TS0 TM1000 X10 Y5"])
    assert _span(rig, 1) == _cycles(rig, 1.100)


def test_tum_p276_a_stop_longer_than_the_move_time_makes_the_move_slower(rig):
    """TM100 X1 = 1000 counts: a stop from 10 counts/ms at Ixx17 = 0.05 would take 200 ms,
    more than the move. The move becomes the triangle where ramp = move time:
    T = sqrt(1000 / 0.05) ms = 141.42 ms, 282.84 ms from start to stop."""
    _setup(rig, "I117=0.05")
    _run(rig, ["LINEAR ABS TA10 TS0 TM100 X1"])
    assert _span(rig, 1) == _cycles(rig, 2 * math.sqrt(1000 / 0.05) / 1000)


def test_tum_p276_short_blended_segments_run_slower_than_programmed(rig):
    """Ten TM10 segments of 100 counts (10 counts/ms): each is calculated as if it were the
    last, so its stop must obey Ixx17 = 0.05: each segment takes sqrt(100 / 0.05) = 44.72 ms
    instead of 10 ms (start to start, to the servo cycle)."""
    _setup(rig, "I117=0.05")
    _run(rig, ["LINEAR INC TA10 TS0 TM10"] + ["X0.1"] * 10)
    starts = sorted(rig.by_n("move_start").values())
    assert len(starts) == 10
    seg = math.sqrt(100 / 0.05) / 1000 / rig.period
    for a, b in zip(starts[1:], starts[2:], strict=False):
        assert abs((b - a) - seg) <= 1


def test_tum_p276_ixx17_above_top_speed_over_segment_time_keeps_the_segments(rig):
    """The manual's rule: Ixx17 > top speed / smallest segment time (10 counts/ms / 10 ms =
    1 count/ms²) does not limit: the TM10 segments keep 10 ms each."""
    _setup(rig, "I117=1.01")
    _run(rig, ["LINEAR INC TA10 TS0 TM10"] + ["X0.1"] * 10)
    starts = sorted(rig.by_n("move_start").values())
    for a, b in zip(starts[1:], starts[2:], strict=False):
        assert abs((b - a) - rig.ms_cycles(10)) <= 1


def test_psrm_p75_the_corner_velocity_change_stretches_the_blend_ramp(rig):
    """PSRM p75's corner: INC F10 TA200 TS0, X20 Y20 then X-20 Y20, 10 000 counts/unit,
    Ixx17 = 0.25. X reverses from +7.07 to -7.07 units/s: 141.4 counts/ms over 200 ms =
    0.707 counts/ms², so the blend ramp becomes 200 × 0.707 / 0.25 = 565.7 ms (the manual
    prints 707 ms, which its own formula gives only for 0.2 ``[INF]``: the formula is kept).
    The first move's ramp from rest (70.7 counts/ms, 0.354 counts/ms²) becomes 282.8 ms. The
    hand-off is half the blend ramp before the corner."""
    _setup(rig, "I117=0.25", "I217=0.25", scale=10000)
    _run(rig, ["INC LINEAR F10 TA200 TS0", "X20 Y20", "X-20 Y20"])
    t1 = 40 * math.sqrt(0.5) / 10  # 28.28 units at 10 units/s
    ta1 = 0.2 * (70.71 / 200) / 0.25
    ta2 = 0.2 * (141.42 / 200) / 0.25
    start = rig.by_n("move_start")
    assert start[3] - start[2] == pytest.approx((ta1 / 2 + t1 - ta2 / 2) / rig.period, abs=1.5)
    assert ta2 == pytest.approx(0.5657, abs=1e-3)


def test_psrm_p74_ixx17_is_computed_at_100_percent_feed_override(rig):
    """ "The calculation does not take into account any feedrate override value other than
    100": at %50 the Ixx17-limited move (282.84 ms at 100 %) takes exactly twice as long."""
    _setup(rig, "I117=0.05", "%50")
    rig.run_for(1.0)  # the % slew (Isx94) has reached 50 %
    _run(rig, ["LINEAR ABS TA10 TS0 TM100 X1"])
    assert _span(rig, 1) == _cycles(rig, 2 * 2 * math.sqrt(1000 / 0.05) / 1000)


def test_psrm_p74_the_corner_velocity_change_is_also_taken_at_100_percent(make_rig):
    """PSRM p75's corner (above) at %50: the corner's velocity change is that of the program
    at 100 %, so the blend ramp and every interval of the corner take exactly twice as long as
    at %100, not the ramp of the halved real velocities."""
    spans = []
    for pct in (100, 50):
        rig = make_rig()
        _setup(rig, "I117=0.25", "I217=0.25", f"%{pct}", scale=10000)
        rig.run_for(1.0)  # the % slew (Isx94) has reached its value
        _run(rig, ["INC LINEAR F10 TA200 TS0", "X20 Y20", "X-20 Y20"])
        start, end = rig.by_n("move_start"), rig.by_n("move_end")
        spans.append((start[3] - start[2], end[3] - start[3]))
    (corner100, last100), (corner50, last50) = spans
    assert corner50 == pytest.approx(2 * corner100, abs=2)
    assert last50 == pytest.approx(2 * last100, abs=2)


def test_s_curve_ramp_peak_acceleration_is_dv_over_ta_minus_ts(rig):
    """``[INF]`` (Delta Tau forum: pure S-curve peak acceleration = V/TS): TA0 TS50 (Ta = 100
    ms) to 10 counts/ms peaks at 0.2 counts/ms²; Ixx17 = 0.1 stretches the ramp to 200 ms."""
    _setup(rig, "I117=0.1")
    _run(rig, ["LINEAR ABS TA0 TS50 TM1000 X10"])
    assert _span(rig, 1) == _cycles(rig, 1.200)


@pytest.mark.parametrize("isx13", [1, 10])
def test_tsrm_p98_segmentation_mode_without_special_lookahead_does_not_use_ixx17(rig, isx13):
    """Isx13 > 0 (1 ms segments too) and no special lookahead: the factory Ixx17 (0.015625)
    is not applied."""
    _setup(rig, f"I5113={isx13}")
    _run(rig, ["LINEAR ABS TA10 TS0 TM100 X10"])
    assert _span(rig, 1) == pytest.approx(rig.ms_cycles(110), abs=1)


def test_factory_ixx17_limits_a_fast_move_of_a_1000_count_per_unit_motor(rig):
    """Ixx17 = 0.015625 counts/ms² (factory): TM100 X4 (4000 counts) becomes the triangle of
    T = sqrt(4000 / 0.015625) = 506 ms, twice that from start to stop."""
    _setup(rig)
    assert float(rig.ok("I117")) == 0.015625
    _run(rig, ["LINEAR ABS TA10 TS0 TM100 X4"])
    assert _span(rig, 1) == _cycles(rig, 2 * math.sqrt(4000 / 0.015625) / 1000)


def test_an_axis_without_a_motor_has_no_acceleration_limit(rig):
    rig.rotary_setup()
    _run(rig, ["LINEAR ABS TA10 TS0 TM100 X1000"])
    assert _span(rig, 1) == pytest.approx(rig.ms_cycles(110), abs=1)


def test_a_move_from_rest_after_the_program_ran_out_has_no_corner(rig):
    """Ixx17 at a corner applies between blended LINEAR moves; a move from rest starts from
    zero velocity. X10 runs, the program runs out of lines (waiting), then X0 arrives: it
    starts from rest, so its ramp is that of X10's from rest (same distance and time), not a
    reversal from X10's velocity (Ixx17 = 0.05 stretches both ramps alike)."""
    _setup(rig, "I117=0.05")
    _run(rig, ["LINEAR ABS TA10 TS0 TM1000 X10"])
    assert rig.c.coord(1)["program"]["state"] == "waiting"
    rig.c.load_lines(1, ["X0"])
    rig.run_until_idle()
    assert _span(rig, 2) == _span(rig, 1) == _cycles(rig, 1.200)


def test_a_motor_of_another_coordinate_system_does_not_limit_this_ones_axis(rig):
    """Ixx16 / Ixx17 are limits of the motors assigned to an axis *in that coordinate
    system* (TUM p201: each CS has its own axis definitions). Motor 1 is X of CS 1 with a low
    Ixx17; a program of CS 2 moving its own X (no motor) is not slowed."""
    rig.ok("&1 #1->1000X")
    rig.ok("I117=0.0001")
    rig.rotary_setup(cs=2)
    rig.c.load_lines(2, ["LINEAR ABS TA10 TS0 TM100 X4"])
    rig.ok("&2 R")
    rig.run_until_idle()
    assert _span(rig, 1) == _cycles(rig, 0.110)
