"""Feedrate override ``%`` and feed hold ``H`` (TSRM p191, p260; spec §4.3, §9.7).

The actual time base slews to a new ``%`` at Isx94 and for ``H`` / the ``R`` after it at Isx95
(2**-23 ms per servo cycle, default 1644: 0 → 100 % in ≈ 1 s). Tests of how moves scale set
Isx94 to its maximum (the change then takes one servo cycle); the slews have their own tests in
``test_time_base_slew.py``."""

from __future__ import annotations

import math

import pytest


def ceil_cycles(rig, ms: float) -> int:
    return math.ceil(rig.ms_cycles(ms) - 1e-6)


def instant(rig) -> None:
    """Isx94 at its maximum for CS 1: a ``%`` change completes in its own servo cycle."""
    rig.ok("I5194=8388607")


def _cycles_of_one_line_at(rig, override: str, line: str) -> int:
    """Set the feedrate ``override`` (``%n``), run ``line`` alone from a fresh rotary buffer;
    servo cycles from its move_start to its move_end."""
    rig.rotary_setup()
    instant(rig)
    rig.ok(override)
    rig.c.load_lines(1, [line])
    rig.ok("R")
    rig.run_until_idle()
    start, end = rig.by_n("move_start")[1], rig.by_n("move_end")[1]
    return end - start


def test_override_set_before_the_move_scales_its_time(make_rig):
    rig = make_rig()
    cycles = _cycles_of_one_line_at(rig, "%50", "TM200 TA50 TS0 X5")
    assert cycles == ceil_cycles(rig, 500)  # (TM + Ta) / 0.5


def test_override_change_mid_move_stretches_the_rest_and_keeps_position_continuous(rig):
    rig.rotary_setup()
    instant(rig)
    rig.c.load_lines(1, ["TM1000 TA100 TS0 X100"])
    rig.ok("R")
    rig.run_for(0.4)
    start = rig.by_n("move_start")[1] * rig.period
    before = rig.c.positions(1)["X"]
    t_change = rig.c.now
    rig.c.coord_system(1).set_feed_override(50)
    assert rig.c.positions(1)["X"] == pytest.approx(before, abs=1e-9)
    rig.run_until_idle()
    end = rig.by_n("move_end")[1] * rig.period
    remaining = start + 1.1 - t_change  # at 100 % the move would end at start + TM + Ta
    assert end == pytest.approx(t_change + 2 * remaining, abs=rig.period)
    assert rig.c.positions(1)["X"] == pytest.approx(100.0)


def test_percent_zero_freezes_motion_and_resuming_continues(rig):
    rig.rotary_setup()
    instant(rig)
    rig.c.load_lines(1, ["TM1000 TA100 TS0 X100", "X200"])
    rig.ok("R")
    rig.run_for(0.3)
    rig.ok("%0")
    x = rig.c.positions(1)["X"]
    rig.run_for(5.0)
    assert rig.c.positions(1)["X"] == x
    assert rig.events("move_end") == []
    rig.ok("%100")
    rig.run_until_idle()
    assert sorted(rig.by_n("move_end")) == [1, 2]
    assert rig.c.positions(1)["X"] == pytest.approx(200.0)


def test_h_holds_and_r_resumes(rig):
    """TSRM p260: H is a feed hold (time base to 0, at Isx95); R resumes."""
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM1000 TA100 TS0 X100"])
    rig.ok("R")
    rig.run_for(0.3)
    rig.ok("H")
    rig.run_for(1.1)  # the Isx95 ramp to 0
    x = rig.c.positions(1)["X"]
    rig.run_for(2.0)
    assert rig.c.positions(1)["X"] == x and rig.events("move_end") == []
    assert rig.ok("%") == "0"
    rig.ok("R")
    rig.run_for(1.1)
    assert rig.ok("%") == "100"
    rig.run_until_idle()
    assert rig.c.positions(1)["X"] == pytest.approx(100.0)


def test_dwell_is_not_scaled_by_the_override(make_rig):
    """TSRM p429: DWELL is real time, not scaled by %."""
    rig = make_rig()
    cycles = _cycles_of_one_line_at(rig, "%25", "DWELL100")
    assert cycles == ceil_cycles(rig, 100)


def test_an_override_change_leaves_a_calculated_dwell_in_real_time(rig):
    """TSRM p429: a DWELL already calculated when ``%`` changes still lasts its own time; the
    moves around it are rescaled."""
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM1000 TA100 TS0 X100", "DWELL500", "X200"])
    instant(rig)
    rig.ok("R")
    rig.run_for(0.3)
    rig.ok("%50")
    rig.run_until_idle()
    start, end = rig.by_n("move_start")[2], rig.by_n("move_end")[2]
    assert end - start == ceil_cycles(rig, 500)
