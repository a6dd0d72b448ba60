"""Ixx16 maximum program velocity for LINEAR moves (TSRM p98; TUM "the move time is extended
so that motor will not exceed its limit") and RAPID at Ixx16 / Ixx22 with the jog ramp
Ixx19-Ixx21 (TSRM p98, p100-101; TUM p286; spec §11.3). Motor 1 is X at 1000 counts per unit.
Times in servo cycles."""

from __future__ import annotations

import math

import pytest


def _setup(rig, *cmds):
    """X = motor 1, Y = motor 2; Ixx17 raised so only the limit under test acts."""
    rig.rotary_setup()
    rig.ok("&1 #1->1000X")
    rig.ok("&1 #2->1000Y")
    rig.ok("I117=1000")
    rig.ok("I217=1000")
    for c in cmds:
        rig.ok(c)


def _cycles(rig, s):
    return math.ceil(s / rig.period - 1e-6)


def _duration(rig, n=None):
    start, end = rig.by_n("move_start"), rig.by_n("move_end")
    n = n if n is not None else min(start)
    return (end[n] - start[n]) * rig.period


def test_tsrm_p98_a_linear_move_over_ixx16_is_slowed_for_all_motors_same_path(rig):
    """X10 in TM100 at 1000 cts/unit asks 100 cts/ms of motor 1; Ixx16 = 20 cts/ms stretches
    the move to 500 ms (+ Ta), and Y (motor 2, well under its limit) slows in proportion."""
    _setup(rig, "I116=20", "I216=1000")
    rig.c.load_lines(1, ["LINEAR ABS TA10 TS0 TM100 X10 Y1"])
    rig.ok("R")
    rig.run_for(0.3)
    pos = rig.c.positions(1)
    assert pos["Y"] == pytest.approx(pos["X"] / 10)  # same straight path
    rig.run_until_idle()
    start, end = rig.by_n("move_start")[1], rig.by_n("move_end")[1]
    assert end - start == _cycles(rig, 0.510)


def test_tsrm_p98_a_move_within_ixx16_keeps_its_programmed_time(rig):
    _setup(rig, "I116=200")
    rig.c.load_lines(1, ["LINEAR ABS TA10 TS0 TM100 X10"])
    rig.ok("R")
    rig.run_until_idle()
    assert _duration(rig) == pytest.approx(0.110, abs=rig.period)


def test_tsrm_p98_ixx16_in_feedrate_mode_extends_the_move_the_same_way(rig):
    _setup(rig, "I116=5", "I5190=1000")
    rig.c.load_lines(1, ["LINEAR ABS TA10 TS0 F100 X10"])  # 100 ms asked, 50 cts/ms
    rig.ok("R")
    rig.run_until_idle()
    assert _duration(rig) == pytest.approx(2.010, abs=rig.period)  # 10000 cts at 5 cts/ms


def test_tsrm_p98_segmentation_mode_without_special_lookahead_does_not_use_ixx16(rig):
    _setup(rig, "I116=20", "I5113=10")
    rig.c.load_lines(1, ["LINEAR ABS TA10 TS0 TM100 X10"])
    rig.ok("R")
    rig.run_until_idle()
    assert _duration(rig) == pytest.approx(0.110, abs=rig.period)


def test_tsrm_p101_rapid_with_ixx90_0_runs_at_the_jog_speed_ixx22_with_the_jog_ramp(rig):
    """Ixx22 = 10 cts/ms, Ixx20 = 100 ms, Ixx21 = 0, Ixx19 large: X10 = 10000 counts takes
    100 ms up, 900 ms at speed, 100 ms down = 1.1 s."""
    _setup(rig, "I190=0", "I122=10", "I120=100", "I121=0", "I119=10")
    rig.c.load_lines(1, ["RAPID ABS X10"])
    rig.ok("R")
    rig.run_for(0.05)
    m = rig.c.coord_system(1).current
    t_mid = m.b_start + 0.55
    assert rig.c.positions(1, t_mid)["X"] == pytest.approx(5.0)
    v = rig.c.coord_system(1)._velocities(m, t_mid)["X"]
    assert v == pytest.approx(10.0)  # 10 cts/ms = 10 units/s at 1000 cts/unit
    rig.run_until_idle()
    assert _duration(rig) == pytest.approx(1.1, abs=rig.period)


def test_tsrm_p98_rapid_with_ixx90_1_runs_at_ixx16(rig):
    _setup(rig, "I190=1", "I116=20", "I122=10", "I120=100", "I121=0", "I119=10")
    rig.c.load_lines(1, ["RAPID ABS X10"])
    rig.ok("R")
    rig.run_until_idle()
    assert _duration(rig) == pytest.approx(0.6, abs=rig.period)  # 100 up, 400, 100 down


def test_tsrm_p100_ixx19_clamps_the_rapid_acceleration_and_extends_the_ramp(rig):
    """The manual's example: Ixx20 = 100, Ixx21 = 0, Ixx22 = 50 asks 0.5 cts/ms²; Ixx19 =
    0.25 makes the ramp 200 ms. 20000 counts: 200 up + 200 at speed + 200 down."""
    _setup(rig, "I190=0", "I122=50", "I120=100", "I121=0", "I119=0.25")
    rig.c.load_lines(1, ["RAPID ABS X20"])
    rig.ok("R")
    rig.run_until_idle()
    assert _duration(rig) == pytest.approx(0.6, abs=rig.period)


def test_tum_p286_rapid_multi_axis_the_slowest_motor_sets_the_time_others_slow_down(rig):
    _setup(rig, "I190=0", "I122=10", "I222=10", "I120=100", "I220=100", "I121=0",
           "I221=0", "I119=10", "I219=10")  # fmt: skip
    rig.c.load_lines(1, ["RAPID ABS X10 Y2"])
    rig.ok("R")
    rig.run_for(0.3)
    pos = rig.c.positions(1)
    assert pos["Y"] == pytest.approx(pos["X"] / 5)
    rig.run_until_idle()
    assert _duration(rig) == pytest.approx(1.1, abs=rig.period)


def test_tum_p341_rapid_is_a_lookahead_break_ending_in_a_stop(rig):
    _setup(rig, "I190=0", "I122=10", "I120=100", "I121=0", "I119=10")
    rig.c.load_lines(1, ["RAPID ABS X1", "LINEAR TA10 TS0 TM50 X2"])
    rig.ok("R")
    rig.run_until_idle()
    start, end = rig.by_n("move_start"), rig.by_n("move_end")
    calc = rig.by_n("line_calculated")
    r = int(rig.c.vars.I(8)) + 1
    assert calc[2] == (end[1] // r + 1) * r  # calculated at the RTI after the RAPID ends
    assert start[2] == calc[2]
