"""Move timing to the servo cycle and planning at RTIs (spec §4, §9.1, §9.3; TUM p236, p339)."""

from __future__ import annotations

import math

import pytest


def ceil_cycles(rig, ms: float) -> int:
    return math.ceil(rig.ms_cycles(ms) - 1e-6)


def next_rti(k: int, m: int = 3) -> int:
    return (k // m + 1) * m


def _run(rig, lines, **cfg):
    rig.rotary_setup()
    rig.c.load_lines(1, lines)
    rig.ok("R")
    rig.run_until_idle()


def _one_line_cycles(rig, line: str) -> int:
    """Run ``line`` alone from a fresh rotary buffer; servo cycles from its move_start to its
    move_end."""
    _run(rig, [line])
    return rig.by_n("move_end")[1] - rig.by_n("move_start")[1]


def test_servo_period_default_from_i10(rig):
    """Spec §4.1: I10 = 3 713 707 × 2**-23 ms = 442.7 µs (≈ 2.26 kHz)."""
    assert rig.period == pytest.approx(442.708e-6, rel=1e-5)


def test_servo_hz_config_overrides_i10(make_rig):
    assert make_rig(servo_hz=1000.0).period == pytest.approx(1e-3)


def test_single_move_from_rest_takes_tm_plus_ta(rig):
    """PUM p169 / spec §9.1: a single move from rest takes TM + Ta."""
    assert _one_line_cycles(rig, "TM200 TA50 TS0 X5") == ceil_cycles(rig, 250)


def test_ta_and_ts_combine_as_max_of_ta_and_twice_ts(rig):
    """Spec §9.1: Ta = max(TA, 2·TS), not TA + TS."""
    assert _one_line_cycles(rig, "TM200 TA50 TS40 X5") == ceil_cycles(rig, 280)


def test_move_time_from_feedrate(rig):
    """TSRM p188-189: ``X3 Y4 F50`` = 5 units at 50 units/s = 100 ms (+ Ta from rest)."""
    assert _one_line_cycles(rig, "TA20 TS0 X3 Y4 F50") == ceil_cycles(rig, 120)


def test_move_shorter_than_ta_takes_ta(rig):
    """Spec §9.1: a move never takes less than its acceleration time."""
    assert _one_line_cycles(rig, "TM10 TA100 TS0 X1") == ceil_cycles(rig, 200)


def test_blended_moves_take_n_tm_plus_ta(rig):
    """Spec §9.1: N blended moves of TM each take N·TM + Ta, each next move starting Ta/2
    before the programmed point."""
    _run(rig, ["TM200 TA50 TS0 X1", "X2", "X3"])
    starts, ends = rig.by_n("move_start"), rig.by_n("move_end")
    k0 = starts[1]
    assert ends[3] - k0 == ceil_cycles(rig, 650)
    assert starts[2] - k0 == ceil_cycles(rig, 200)
    assert starts[3] - k0 == ceil_cycles(rig, 400)
    assert ends[1] == starts[2] and ends[2] == starts[3]


def test_motion_starts_at_the_first_rti_after_r(rig):
    """TUM p236, p339: R's first moves are calculated at the next RTI and start (I11=0)."""
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM100 TA10 TS0 X1"])
    r = rig.cmd("R")
    k_r = rig.cyc(r.t_done)
    rig.run_until_idle()
    assert rig.by_n("line_calculated")[1] == next_rti(k_r)
    assert rig.by_n("move_start")[1] == next_rti(k_r)


def test_rti_period_follows_i8(make_rig):
    """RTI every I8+1 servo cycles."""
    rig = make_rig(i8=4)
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM100 TA10 TS0 X1"])
    r = rig.cmd("R")
    rig.run_until_idle()
    assert rig.by_n("move_start")[1] == next_rti(rig.cyc(r.t_done), 5)


def test_linear_calculates_two_moves_ahead(rig):
    """Spec §4.2/§9.3 (Isx13=0, LINEAR): from rest the scan runs through the 3rd move; each
    later line is calculated at the first RTI after the move two before it starts."""
    _run(rig, ["TM100 TA10 TS0 X1", "X2", "X3", "X4", "X5", "X6"])
    calc, starts = rig.by_n("line_calculated"), rig.by_n("move_start")
    assert calc[1] == calc[2] == calc[3] == starts[1]
    for n in (4, 5, 6):
        assert calc[n] == next_rti(starts[n - 2])


def test_circles_without_segmentation_run_as_linear_and_calculate_two_moves_ahead(rig):
    """TSRM p177 (spec §4.3): CIRCLE1/2 need Isx13 > 0; with Isx13 = 0 they run as LINEAR
    moves, so lookahead is LINEAR's two moves (TUM p339, spec §4.2)."""
    _run(rig, ["CIRCLE1 TM100 TA10 TS0 X1 I1", "X2 I1", "X3 I1", "X4 I1", "X5 I1", "X6 I1"])
    calc, starts = rig.by_n("line_calculated"), rig.by_n("move_start")
    assert calc[1] == calc[2] == calc[3] == starts[1]
    for n in (4, 5, 6):
        assert calc[n] == next_rti(starts[n - 2])


def test_segmented_mode_calculates_one_move_ahead(make_rig):
    """Spec §9.3: with Isx13 > 0, one move ahead."""
    rig = make_rig(i5113=10)
    _run(rig, ["TM100 TA10 TS0 X1", "X2", "X3", "X4"])
    calc, starts = rig.by_n("line_calculated"), rig.by_n("move_start")
    assert calc[1] == calc[2] == starts[1]
    for n in (3, 4):
        assert calc[n] == next_rti(starts[n - 1])


def test_dwell_stops_lookahead(rig):
    """TUM p341 / TSRM p429: nothing after a DWELL is calculated during it; the move before
    it decelerates to a stop first; calculation resumes at the RTI after the dwell."""
    _run(rig, ["TM100 TA10 TS0 X1", "DWELL50", "X2", "X3"])
    calc, starts, ends = (rig.by_n(t) for t in ("line_calculated", "move_start", "move_end"))
    k0 = starts[1]
    assert calc[2] == k0  # the dwell itself is calculated
    assert ends[1] - k0 == ceil_cycles(rig, 110)  # stop before the dwell
    assert starts[2] == ends[1]
    assert ends[2] - starts[2] == ceil_cycles(rig, 50)
    assert calc[3] == calc[4] == starts[3] == next_rti(ends[2])


def test_delay_does_not_stop_lookahead(rig):
    """TUM p341: DELAY is a zero-distance move, calculated through."""
    _run(rig, ["TM100 TA10 TS0 X1", "DELAY50", "X2", "X3"])
    calc, starts, ends = (rig.by_n(t) for t in ("line_calculated", "move_start", "move_end"))
    assert calc[1] == calc[2] == calc[3] == starts[1]
    assert starts[2] == ends[1]  # blended, no stop


def test_positions_come_from_the_profile(rig):
    """Positions at any instant without a servo-cycle event: cruise is linear in time."""
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM1000 TA100 TS0 X100"])
    rig.ok("R")
    rig.run_for(0.3)
    k0 = rig.by_n("move_start")[1]
    t0 = k0 * rig.period
    # Programmed start point passed at t0 + Ta/2, then 100 units/s.
    p = rig.c.positions(1)["X"]
    assert p == pytest.approx(100 * (rig.c.now - t0 - 0.05), abs=1e-9)
    rig.run_until_idle()
    assert rig.c.positions(1) == {"X": 100.0}


def test_incremental_mode(rig):
    """INC makes axis values distances."""
    _run(rig, ["INC TM100 TA10 TS0 X5", "X5"])
    assert rig.c.positions(1)["X"] == pytest.approx(10.0)


@pytest.mark.parametrize("i11", [10, 2000])
def test_i11_delays_the_start_after_calculation(make_rig, i11):
    """PSRM I11: "the delay from when the run signal is taken ... and when the first programmed
    move starts" (ms); the moves are calculated (at the first RTI) before that. 2000 ms is
    4518 servo cycles to the cycle."""
    rig = make_rig(i11=i11)
    _run(rig, ["TM100 TA10 TS0 X1", "X2"])
    calc, starts = rig.by_n("line_calculated"), rig.by_n("move_start")
    (k_r, _, _), *_ = rig.events("program")  # R taken: running
    assert calc[1] == next_rti(k_r) < starts[1] == k_r + ceil_cycles(rig, i11)


def test_isx92_disables_blending_and_lookahead(make_rig):
    """TSRM p190 / TUM p341: with Isx92 = 1 every move stops, and the next move is calculated
    (at the next RTI) only after it; continuous-motion-request bit is 0."""
    rig = make_rig(i5192=1)
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM100 TA10 TS0 X1", "X2", "X3"])
    rig.ok("R")
    word1 = int(rig.ok("??")[:6], 16)
    assert word1 & 1 and not word1 & (1 << 4)
    rig.run_until_idle()
    calc, starts, ends = (rig.by_n(t) for t in ("line_calculated", "move_start", "move_end"))
    for n in (1, 2, 3):
        assert ends[n] - starts[n] == ceil_cycles(rig, 110)  # every move from rest to rest
    for n in (2, 3):
        assert calc[n] == starts[n] == next_rti(ends[n - 1])


def test_a_delay_lasts_at_least_the_ta_set_on_its_own_line(make_rig):
    """TUM p341: DELAY is a zero-distance move of the given time, and a move lasts at least
    its acceleration time (spec §9.1). With ``TA200`` on the DELAY's own line, ``DELAY100``
    runs exactly as ``DELAY200`` (both last the 200-ms ramp), and longer than ``DELAY50``
    under the TA10 of the line before."""
    spans = {}
    for line in ("TA200 DELAY100", "TA200 DELAY200", "DELAY50"):
        rig = make_rig()
        _run(rig, ["TM100 TA10 TS0 X1", line, "X2"])
        spans[line] = rig.by_n("move_end")[2] - rig.by_n("move_start")[2]
    assert spans["TA200 DELAY100"] == spans["TA200 DELAY200"] > spans["DELAY50"]


@pytest.mark.parametrize(
    ("lines", "end"),
    [
        (["TM100 TA10 TS0 X1", "DELAY100", "X2"], 2.0),
        (["TM100 TA10 TS0 SPLINE1 X1", "X2", "X3"], 3.0),
    ],
    ids=["delay", "spline1"],
)
def test_isx92_makes_a_delay_and_each_spline_point_a_break_too(make_rig, lines, end):
    """TSRM p190: Isx92 = 1 stops lookahead at every move — a DELAY (a move, TUM p341) and each
    SPLINE1 point ``[INF]`` included: each line after the first is calculated only once the
    move before it has ended, at the next RTI."""
    rig = make_rig(i5192=1)
    _run(rig, lines)
    calc, ends = rig.by_n("line_calculated"), rig.by_n("move_end")
    for n in (2, 3):
        assert calc[n] == next_rti(ends[n - 1])
    assert rig.c.positions(1) == {"X": pytest.approx(end)}


def test_program_expressions_are_evaluated_at_calculation(rig):
    """TUM p244: a motion program's axis words and variable numbers may be expressions, taken
    when the line is calculated: ``P(P1)=7`` writes P3 (P1 = 3), ``X(P1*2)`` moves to 6."""
    _run(rig, ["P1=3", "P(P1)=7 TM100 TA10 TS0 X(P1*2)"])
    assert rig.ok("P3") == "7"
    assert rig.c.positions(1) == {"X": pytest.approx(6.0)}
