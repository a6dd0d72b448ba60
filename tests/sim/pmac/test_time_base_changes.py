"""A ``%`` / ``H`` change of the time base in the middle of things (TSRM p191, p260, p429;
PSRM Ix95; spec §4.3): what moves, what waits and where the next move starts.

The time base stretches the rest of the executing move around the instant it changes and
rescales the calculated moves; the next move still starts where the blend into it begins
(spec §9.1: Ta/2 of the *next* move before the programmed point), or, in segmentation mode
(Isx13 > 0) and PVT / SPLINE, at the executing move's decision point. Changes here are made
instant (Isx94 = Isx95 = 8388607: one servo cycle covers them) unless a test is about the slew.
Times are servo cycles.
"""

from __future__ import annotations

import math

import pytest

MAX_RATE = "8388607"


def _cycle_at_or_after(rig, t: float) -> int:
    return math.ceil(t / rig.period - 1e-6)


def _instant(rig) -> None:
    rig.ok(f"I5194={MAX_RATE}")
    rig.ok(f"I5195={MAX_RATE}")


def _stretched(t_change: float, t: float, k: float) -> float:
    """An instant ``t`` of the executing move after the time base changes at ``t_change`` by
    the stretch factor ``k`` (old % / new %)."""
    return t_change + (t - t_change) * k


def test_percent_zero_before_r_holds_the_calculated_move_and_percent_100_starts_it(rig):
    """With the time base at 0 nothing moves: ``R`` calculates the first moves but none
    starts (the program is running, not waiting); ``%100`` starts the first one in the
    command's own servo cycle."""
    rig.rotary_setup()
    _instant(rig)
    rig.ok("%0")
    rig.c.load_lines(1, ["TM200 TA100 TS0 X10"])
    rig.ok("R")
    rig.run_for(0.5)
    assert rig.events("move_start") == []
    assert [f["state"] for _, _, f in rig.events("program")] == ["running"]
    k = rig.cyc(rig.cmd("%100").t_done)
    rig.run_until_idle()
    assert rig.by_n("move_start") == {1: k}
    assert rig.c.positions(1)["X"] == pytest.approx(10.0)


def test_a_long_percent_zero_freeze_delays_the_move_end_by_exactly_the_time_frozen(make_rig):
    """``%0`` freezes the move where it is; ``%100`` continues it from there: the move ends
    exactly as much later as it was frozen (here frozen for much longer than it had run)."""
    line = "TM1000 TA100 TS0 X1000"

    def run(freeze: bool) -> tuple[int, dict]:
        rig = make_rig()
        rig.rotary_setup()
        _instant(rig)
        rig.c.load_lines(1, [line])
        rig.ok("R")
        rig.run_for(0.3)
        if freeze:
            k0 = rig.cyc(rig.cmd("%0").t_done)
            x0 = rig.c.positions(1)["X"]
            rig.run_for(2.5)
            assert rig.c.positions(1)["X"] == x0
            k1 = rig.cyc(rig.cmd("%100").t_done)
            rig.run_for(rig.period)
            assert rig.c.positions(1)["X"] == pytest.approx(x0, abs=1.0)  # continuous
            frozen = k1 - k0
        else:
            frozen = 0
        rig.run_until_idle()
        return rig.by_n("move_end")[1] - frozen, rig.c.positions(1)

    assert run(True) == run(False)


def test_percent_after_h_ends_the_hold_the_next_r_does_not_ramp_again(rig):
    """``%n`` after ``H`` ends the hold: the time base goes to n at Isx94; an ``R`` given
    then is no "resume from hold" and does not start an Isx95 ramp ``[INF]``."""
    rig.rotary_setup()
    rig.ok(f"I5195={MAX_RATE}")  # H / R after H: one cycle
    rig.ok("I5194=1644")  # %: ≈ 0.044 % a cycle
    rig.ok("H")
    rig.run_for(0.01)
    assert rig.ok("%") == "0"
    rig.ok("%50")
    rig.ok("R")
    rig.run_for(0.05)
    pct = float(rig.ok("%"))
    assert 0 < pct < 10  # still on the slow Isx94 slew, not jumped to 50 at Isx95
    rig.run_for(2.0)
    assert rig.ok("%") == "50"


def test_isx94_zero_leaves_the_time_base_and_a_later_rate_does_not_re_arm_the_slew(rig):
    """Isx94 = 0: a slew rate of nothing per cycle never reaches the new value, ``%`` keeps
    reporting the old one; setting a rate afterwards changes nothing until the next ``%``
    ``[INF]`` (the rate is read at every step of a slew, and a rate of 0 ends it)."""
    rig.ok("I5194=0")
    rig.ok("%50")
    rig.run_for(0.5)
    assert rig.ok("%") == "100"
    rig.ok("I5194=1644")
    rig.run_for(2.0)
    assert rig.ok("%") == "100"
    rig.ok("%50")
    rig.run_for(2.0)
    assert rig.ok("%") == "50"


def test_a_percent_change_moves_the_hand_off_to_the_stretched_start_of_the_next_blend(rig):
    """Isx13 = 0, three moves calculated: ``%50`` during the first stretches its rest and the
    calculated moves' ramps; the second move still starts where the blend into it begins,
    TA/2 of the *second* move (stretched) before the first one's stretched end point — not
    the first move's own TA/2, nor the third's."""
    rig.rotary_setup()
    _instant(rig)
    rig.c.load_lines(1, ["TM1000 TA100 TS0 X1000", "TA400 X2000", "TA100 X3000"])
    rig.ok("R")
    rig.run_for(0.05)
    k0 = rig.by_n("move_start")[1]
    t0 = k0 * rig.period
    rig.run_for(0.3)
    t_c = rig.cyc(rig.cmd("%50").t_done) * rig.period
    rig.run_until_idle()
    b_end = _stretched(t_c, t0 + 0.05 + 1.0, 2.0)  # the first move's programmed end point
    k2 = _cycle_at_or_after(rig, b_end - 0.4)  # the second move's TA 400 ms at 50 %: 800 ms
    assert rig.by_n("move_start")[2] == rig.by_n("move_end")[1] == k2
    assert rig.c.positions(1)["X"] == pytest.approx(3000.0)


def test_segmented_mode_percent_change_then_a_line_before_deceleration_still_blends(make_rig):
    """Isx13 > 0: after ``%50`` during the last move in the buffer, a line arriving before
    the (stretched) deceleration to a stop starts is blended in (seed 000, PUM p213): the next
    move starts at the first move's decision point, Ta/2 before its stretched end."""
    rig = make_rig(i5113=10)
    rig.rotary_setup()
    _instant(rig)
    rig.c.load_lines(1, ["TM500 TA100 TS0 X10"])
    rig.ok("R")
    rig.run_for(0.05)
    t0 = rig.by_n("move_start")[1] * rig.period
    rig.run_for(0.15)
    t_c = rig.cyc(rig.cmd("%50").t_done) * rig.period
    rig.run_for(0.2)
    rig.c.load_lines(1, ["X20"])
    rig.run_until_idle()
    b_end = _stretched(t_c, t0 + 0.05 + 0.5, 2.0)
    k2 = _cycle_at_or_after(rig, b_end - 0.1)  # Ta 100 ms at 50 %: 200 ms, half of it
    assert rig.by_n("move_start")[2] == rig.by_n("move_end")[1] == k2
    assert [f["state"] for _, _, f in rig.events("program")] == ["running", "waiting"]


def test_pvt_percent_change_mid_segment_the_next_segment_starts_at_the_stretched_end(rig):
    """PVT segments abut without a ramp (TSRM p463): ``%50`` in the middle of a segment
    stretches its rest, the next segment starts exactly at its stretched end."""
    rig.rotary_setup()
    _instant(rig)
    rig.c.load_lines(1, ["PVT500 X50:100", "X100:0"])
    rig.ok("R")
    rig.run_for(0.05)
    t0 = rig.by_n("move_start")[1] * rig.period
    rig.run_for(0.35)
    t_c = rig.cyc(rig.cmd("%50").t_done) * rig.period
    rig.run_until_idle()
    k2 = _cycle_at_or_after(rig, _stretched(t_c, t0 + 0.5, 2.0))
    assert rig.by_n("move_start")[2] == rig.by_n("move_end")[1] == k2
    assert rig.by_n("move_end")[2] == _cycle_at_or_after(rig, k2 * rig.period + 1.0)
    assert rig.c.positions(1)["X"] == pytest.approx(100.0)


def test_spline_percent_change_the_closing_move_waits_for_the_stretched_end(rig):
    """SPLINE1: with the buffer read to its end, the last point's move (with the added
    segment to rest, TUM p290) is calculated when the move before it ends; ``%50`` during that
    move stretches it and the last point's move starts at its stretched end, not earlier."""
    rig.rotary_setup()
    _instant(rig)
    rig.c.load_lines(1, ["SPLINE1 TM200 X10", "X20", "X30"])
    rig.ok("R")
    rig.run_until_idle(0.05)
    while 2 not in rig.by_n("move_start"):
        rig.run_for(rig.period)
    starts = rig.by_n("move_start")
    t1 = starts[1] * rig.period
    # the first move is the added lead-in segment and its own: 400 ms, the second 200 ms
    assert starts[2] == _cycle_at_or_after(rig, t1 + 0.4)
    rig.run_for(0.1)
    t_c = rig.cyc(rig.cmd("%50").t_done) * rig.period
    rig.run_until_idle()
    k3 = _cycle_at_or_after(rig, _stretched(t_c, t1 + 0.6, 2.0))
    assert rig.by_n("move_start")[3] == rig.by_n("move_end")[2] == k3
    assert rig.c.positions(1)["X"] == pytest.approx(30.0)
