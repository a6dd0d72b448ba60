"""MERGE and SRAMP on the Trio profile generator, in virtual time on the event log.

Sources: neither TRM page was reachable (spec §1.6, §9.7, §9.11 ``[BK]``); the rules tested
are the ones written down in :mod:`motionsim.sim.trio.buffers` (MERGE: with MERGE ON on the base
axis and the next move loaded in NTYPE, the axis does not ramp down to zero between the moves) and
:mod:`motionsim.sim.trio.profile` (SRAMP: ms over which the acceleration ramps to ACCEL / DECEL; a
move that reaches SPEED lasts SRAMP longer).

Axis settings (conftest): SPEED 1000, ACCEL = DECEL = 100 000, servo period 1 ms. A MOVE(100)
from rest to rest takes 110 periods: 10 ramping up (5 units), 90 cruising, 10 ramping down.
"""

from __future__ import annotations

import math

import pytest
from motionsim.sim.errors import InvalidValue

from tests.sim.trio.conftest import cycle, fields, make, next_period, run_to


def _starts_ends(c, axis: int = 0) -> tuple[list[int], list[int]]:
    starts = [cycle(c, t) for t, _ in fields(c, "move_start", axis=axis)]
    ends = [cycle(c, t) for t, _ in fields(c, "move_end", axis=axis)]
    return starts, ends


def _dpos_at(c, t: float, axis: int = 0) -> float:
    run_to(c, t)
    return c.axis(axis)["dpos"]


# -- MERGE ---------------------------------------------------------------------------------


def test_merge_off_by_default_moves_stop_between():
    """MERGE defaults to OFF: each MOVE(100) ramps down to rest, the next starts a period
    after (TN20 pull-forward)."""
    c = make()
    assert c.axis(0)["merge"] == 0.0
    c.move(0, "MOVE", [100])
    next_period(c)  # each move transits the process buffer
    c.move(0, "MOVE", [100])
    c.env.run()
    assert _starts_ends(c) == ([1, 112], [111, 222])


def test_merge_on_second_move_loaded_runs_through_at_speed():
    """MERGE ON, the next move already in NTYPE: the first move ends at SPEED without its
    ramp down (10 periods shorter, ends at 1 + 105), the second takes over MTYPE in that same
    servo period at SPEED with no ramp up (its profile picks up where the first left off) and only
    ramps down at its end: 5 + 90 + 95 + 5 units in 0.21 s."""
    c = make()
    c.set_axis(0, merge=1)
    c.move(0, "MOVE", [100])
    next_period(c)  # each move transits the process buffer
    c.move(0, "MOVE", [100])
    assert _dpos_at(c, 0.0505) == pytest.approx(44.0)  # 5 ramping + 39 cruising
    assert _dpos_at(c, 0.1065) == pytest.approx(100.0)  # cycle 106: the joint
    assert _dpos_at(c, 0.1075) == pytest.approx(101.0)  # cycle 107: on at 1000 units/s
    assert c.axis(0)["vp_speed"] == pytest.approx(1000.0)
    assert _dpos_at(c, 0.2005) == pytest.approx(194.0)  # still cruising: no ramp between
    c.env.run()
    assert _starts_ends(c) == ([1, 106], [106, 211])
    assert c.axis(0)["dpos"] == pytest.approx(200.0)
    # at a merged joint the next move takes over MTYPE in the period the first ends
    kinds = [(e.type, cycle(c, e.t)) for e in c.log.events("move_start", "move_end")]
    assert kinds == [("move_start", 1), ("move_end", 106), ("move_start", 106),
                     ("move_end", 211)]


def test_merge_streams_from_a_program_through_the_process_buffer():
    """A BASIC program sets MERGE ON and issues three MOVE(100): the third waits in the
    process buffer, reaches NTYPE two periods after the first move ends, and the second move
    (then cruising) merges into it, so only the first ramps up and only the last ramps down:
    durations 0.105, 0.100, 0.105 s instead of 0.110 each."""
    c = make()
    c.store_program("M", "MERGE=ON\nMOVE(100)\nMOVE(100)\nMOVE(100)\n")
    c.run_program("M", 1)
    c.env.run()
    starts, ends = _starts_ends(c)
    s1 = starts[0]
    assert [e - s1 for e in ends] == [105, 205, 310]
    assert [s - s1 for s in starts] == [0, 105, 205]
    assert c.axis(0)["dpos"] == pytest.approx(300.0)


def test_merge_too_late_once_the_ramp_down_has_begun():
    """MOVE(10) is a triangle that starts ramping down 10 periods after its start. A next
    move loaded after that point is not merged (the controller already slows down: the TRM's
    warning about short moves); loaded before it, the first move runs to its end at speed."""
    late = make()
    late.set_axis(0, merge=1)
    late.move(0, "MOVE", [10])
    run_to(late, 0.0155)
    late.move(0, "MOVE", [10])
    late.env.run()
    assert _starts_ends(late) == ([1, 22], [21, 42])

    early = make()
    early.set_axis(0, merge=1)
    early.move(0, "MOVE", [10])
    run_to(early, 0.0055)
    early.move(0, "MOVE", [10])
    early.env.run()
    starts, ends = _starts_ends(early)
    # first: 5 units ramping up in 0.01 s, then 5 at SPEED: ends at 1 + 15
    assert ends[0] == 16 and starts[1] == 16
    # second: from 1000 units/s, 5 units cruising then 5 ramping down: 0.015 s after 0.016
    assert ends[1] == 31
    assert early.axis(0)["dpos"] == pytest.approx(20.0)


def test_merge_needs_the_same_axis_group_and_a_profiled_move():
    """Only MOVE / MOVEABS / MOVECIRC / MHELICAL on the same axes merge: a MOVE on axis 0
    followed by a 2-axis MOVE on BASE(0,1) stops in between as without MERGE."""
    c = make()
    c.set_axis(0, merge=1)
    c.move(0, "MOVE", [100])
    next_period(c)  # each move transits the process buffer
    c.move(0, "MOVE", [100, 0])
    c.env.run()
    assert _starts_ends(c) == ([1, 112], [111, 222])


def test_cancel_of_a_merged_move_ramps_down_and_the_next_starts_from_rest():
    """CANCEL of a move merged onto the next: it decelerates at DECEL (10 periods from SPEED)
    and the NTYPE move then starts from rest, as after any move end."""
    c = make()
    c.set_axis(0, merge=1)
    c.move(0, "MOVE", [100])
    next_period(c)  # each move transits the process buffer
    c.move(0, "MOVE", [100])
    run_to(c, 0.0505)
    c.buffers.cancel(0)
    c.env.run()
    starts, ends = _starts_ends(c)
    assert ends[0] == 60 and starts[1] == 61
    assert ends[1] == 61 + 110


def test_merge_parameter_values():
    """MERGE is a switch: any non-zero value (TRUE = -1) reads back ON = 1."""
    c = make()
    c.set_axis(0, merge=-1)
    assert c.axis(0)["merge"] == 1.0
    c.set_axis(0, merge=0)
    assert c.axis(0)["merge"] == 0.0


# -- SRAMP ---------------------------------------------------------------------------------


def test_sramp_lengthens_a_move_that_reaches_speed_by_sramp():
    """SRAMP 5 ms: each ramp to or from SPEED takes 10 + 5 ms and covers 7.5 units, so
    MOVE(100) lasts 115 periods instead of 110; DPOS follows the S: after the first 5 ms
    (acceleration reaching ACCEL with jerk 2e7) it is jerk·t³/6."""
    c = make()
    c.set_axis(0, sramp=5)
    c.move(0, "MOVE", [100])
    assert _dpos_at(c, 0.0065) == pytest.approx(2e7 * 0.005 ** 3 / 6)
    assert _dpos_at(c, 0.0165) == pytest.approx(7.5)  # ramp up done, at SPEED
    assert c.axis(0)["vp_speed"] == pytest.approx(1000.0)
    assert _dpos_at(c, 0.0585) == pytest.approx(49.5)  # cruising
    assert _dpos_at(c, 0.1015) == pytest.approx(100.0 - 7.5)  # ramp down starts
    c.env.run()
    assert _starts_ends(c) == ([1], [116])
    assert c.axis(0)["dpos"] == pytest.approx(100.0)


def test_sramp_zero_is_the_trapezoid():
    c = make()
    c.set_axis(0, sramp=0)
    c.move(0, "MOVE", [100])
    c.env.run()
    assert _starts_ends(c) == ([1], [111])


def test_sramp_short_move_peaks_below_accel():
    """MOVE(1) with SRAMP 5 ms never reaches ACCEL: each ramp is two jerk phases of
    sqrt(vp·Ts/A) and the peak speed vp solves 2·vp·sqrt(vp·Ts/A) = 1 (vp ≈ 171 units/s):
    0.0117 s, so the move ends 12 periods after its start."""
    ts, a = 0.005, 1e5
    vp = (1.0 / (2.0 * math.sqrt(ts / a))) ** (2.0 / 3.0)
    duration = 4.0 * math.sqrt(vp * ts / a)
    c = make()
    c.set_axis(0, sramp=5)
    c.move(0, "MOVE", [1])
    run_to(c, 0.001 + duration / 2 + 1e-4)
    assert c.axis(0)["vp_speed"] == pytest.approx(vp, rel=0.05)
    c.env.run()
    assert _starts_ends(c) == ([1], [1 + math.ceil(duration / 0.001)])
    assert c.axis(0)["dpos"] == pytest.approx(1.0)


def test_sramp_with_merge_keeps_the_s_only_at_the_outer_ramps():
    """SRAMP and MERGE together: two MOVE(100) run as one S-curve move of 200 units,
    0.215 s (0.21 + SRAMP)."""
    c = make()
    c.set_axis(0, merge=1, sramp=5)
    c.move(0, "MOVE", [100])
    next_period(c)  # each move transits the process buffer
    c.move(0, "MOVE", [100])
    c.env.run()
    starts, ends = _starts_ends(c)
    assert ends[-1] == 1 + 215
    assert c.axis(0)["dpos"] == pytest.approx(200.0)


def test_sramp_out_of_range_is_refused_and_changes_nothing():
    c = make()
    with pytest.raises(InvalidValue) as err:
        c.set_axis(0, sramp=300, speed=10)
    assert err.value.details["field"] == "sramp"
    assert c.axis(0)["sramp"] == 0.0 and c.axis(0)["speed"] == 1000.0


def test_sramp_from_basic():
    """``SRAMP=5`` in a program writes the base axis' parameter (ms)."""
    c = make()
    c.store_program("S", "SRAMP=5\nMOVE(100)\n")
    c.run_program("S", 1)
    c.env.run()
    starts, ends = _starts_ends(c)
    assert ends[0] - starts[0] == 115


def test_example_merge_stream_runs_as_one_s_curve_move():
    """``examples/trio/merge_stream.bas``: five merged MOVE(100) with SRAMP 5 ms take
    0.5 s at SPEED + 0.01 s for the two ramps + 0.005 s SRAMP, one ramp up, one down."""
    from pathlib import Path

    text = (Path(__file__).resolve().parents[3] / "examples/trio/merge_stream.bas").read_text()
    c = make()
    c.store_program("MS", text)
    c.run_program("MS", 1)
    c.env.run()
    starts, ends = _starts_ends(c)
    # first: S-ramp up (0.015 s, 7.5 units) + 92.5 units at SPEED = 0.1075 s, ends on the
    # next servo period; the middle three are 0.1 s each at SPEED; the last adds the ramp down
    assert [e - starts[0] for e in ends] == [108, 208, 308, 408, 515]
    assert c.axis(0)["dpos"] == pytest.approx(500.0)


def test_merge_of_interpolated_moves_uses_the_base_axis_merge():
    """Two MOVE(30,40) on BASE(0,1) (50 units along the path each) merge when MERGE is ON on
    the base axis 0 only: both axes end the first move at 1 + 55 and the second at 111, and
    at cycle 80 the path is 50 + 24 = 74 units along (x = 0.6·74, y = 0.8·74): the second
    move, started on at SPEED from t = 0.056, has run 24 ms."""
    c = make()
    c.set_axis(0, merge=1)
    c.move(0, "MOVE", [30, 40])
    next_period(c)  # each move transits the process buffer
    c.move(0, "MOVE", [30, 40])
    run_to(c, 0.0805)
    assert c.axis(0)["dpos"] == pytest.approx(0.6 * 74)
    assert c.axis(1)["dpos"] == pytest.approx(0.8 * 74)
    c.env.run()
    for axis in (0, 1):
        assert _starts_ends(c, axis) == ([1, 56], [56, 111])
    assert (c.axis(0)["dpos"], c.axis(1)["dpos"]) == pytest.approx((60.0, 80.0))
