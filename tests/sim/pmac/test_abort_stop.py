"""``A``: each motor decelerates to a stop at its own abort rate Ixx15, not along the
programmed path (TUM p319; PSRM p73 Ixx15 in counts/ms²). Times in servo cycles."""

from __future__ import annotations

import math

import pytest
from motionsim.sim.pmac.lookahead import abort_stop


def _abort_during(rig, lines, after_s):
    rig.rotary_setup()
    rig.c.load_lines(1, lines)
    rig.ok("R")
    rig.run_for(after_s)
    cs = rig.c.coord_system(1)
    vel = cs._velocities(cs.current, rig.c.now)
    reply = rig.cmd("A")
    return rig.c.now, rig.c.positions(1), vel, rig.cyc(reply.t_done)


def test_each_axis_stops_at_its_own_rate_so_the_slow_axis_stops_first(rig):
    """No motors: every axis at motor 1's Ixx15, one count per unit ``[INF]``. I115 = 0.001
    counts/ms² = 1000 units/s². X at 100 units/s stops after 100 ms and 5 units, Y at
    10 units/s after 10 ms and 0.05 units: 20 ms after ``A`` Y is at rest, X still moving."""
    rig.ok("I115=0.001")
    t_a, pos, vel, k_a = _abort_during(rig, ["TM1000 TA10 TS0 X100 Y10"], 0.5)
    assert vel == {"X": pytest.approx(100.0), "Y": pytest.approx(10.0)}
    rig.run_for(0.02)
    mid = rig.c.positions(1)
    assert mid["Y"] == pytest.approx(pos["Y"] + 0.05)
    assert mid["X"] < pos["X"] + 5 - 1e-3
    assert mid["X"] - pos["X"] != pytest.approx(10 * (mid["Y"] - pos["Y"]))  # off the path
    rig.run_until_idle()
    assert rig.by_n("move_end")[1] == math.ceil((t_a + 0.1) / rig.period - 1e-6)
    assert rig.c.positions(1) == {  # to 1e-9: the rate is Ixx15 x 10^6 exactly
        "X": pytest.approx(pos["X"] + 5.0, abs=1e-9), "Y": pytest.approx(pos["Y"] + 0.05, abs=1e-9)
    }


def test_an_axis_decelerates_at_its_own_motors_ixx15_over_its_counts_per_unit(rig):
    """``#1->300X`` with I115 = 0.1 counts/ms² decelerates X at 100 000 / 300 = 333.3
    units/s²; ``#2->100Y`` with I215 = 0.1 at 1000 units/s². X at 10 units/s stops after 30 ms
    (0.15 units), Y at 10 units/s after 10 ms (0.05 units)."""
    for cmd in ("&1 #1->300X", "&1 #2->100Y", "I115=0.1", "I215=0.1", "I116=1000",
                "I216=1000", "I117=1000", "I217=1000"):
        rig.ok(cmd)
    t_a, pos, vel, _ = _abort_during(rig, ["TM1000 TA10 TS0 X10 Y10"], 0.5)
    assert vel == {"X": pytest.approx(10.0), "Y": pytest.approx(10.0)}
    rig.run_for(0.02)
    assert rig.c.positions(1)["Y"] == pytest.approx(pos["Y"] + 0.05)
    rig.run_until_idle()
    assert rig.by_n("move_end")[1] == math.ceil((t_a + 0.03) / rig.period - 1e-6)
    assert rig.c.positions(1) == {
        "X": pytest.approx(pos["X"] + 0.15, abs=1e-9), "Y": pytest.approx(pos["Y"] + 0.05, abs=1e-9)
    }


def test_r_after_the_abort_stop_starts_from_where_the_axes_came_to_rest(rig):
    """A line sent after the abort runs from the stop point: its move starts where X and Y
    each came to rest, and ends at its programmed point."""
    rig.ok("I115=0.001")
    _, pos, _, _ = _abort_during(rig, ["TM1000 TA10 TS0 X100 Y10"], 0.5)
    rig.run_until_idle()
    rest = rig.c.positions(1)
    assert rest == {"X": pytest.approx(pos["X"] + 5.0), "Y": pytest.approx(pos["Y"] + 0.05)}
    rig.c.load_lines(1, ["X0 Y0"])
    rig.ok("R")
    rig.run_for(0.005)
    assert rig.c.coord_system(1).current.start == rest
    rig.run_until_idle()
    assert rig.c.positions(1) == {"X": pytest.approx(0.0), "Y": pytest.approx(0.0)}


def _slow_move_at(rig, pct: int) -> None:
    """I115 = 0.00001 counts/ms²; X moving at 100 units/s, then ``%{pct}`` typed and reached
    (the Isx94 slew is over after 2 s)."""
    rig.ok("I115=0.00001")
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM100000 TA10 TS0 X10000"])
    rig.ok("R")
    rig.run_for(0.05)
    rig.ok(f"%{pct}")
    rig.run_for(2.0)


def test_the_abort_stop_starts_from_the_velocity_at_the_feed_override_in_force(rig):
    """At ``%1`` X, programmed at 100 units/s, moves at 1 unit/s (TSRM p191); ``A`` stops it
    from that velocity: at I115 = 0.00001 counts/ms² (10 units/s²) in 100 ms and 0.05 units.
    At ``%0`` (time base frozen) nothing moves and ``A`` stops at once (below)."""
    _slow_move_at(rig, 1)
    cs = rig.c.coord_system(1)
    assert cs._velocities(cs.current, rig.c.now)["X"] == pytest.approx(1.0)
    rig.ok("A")
    t_a, x_a = cs._abort.t0, cs._abort.pos["X"]  # the instant A was taken
    rig.run_until_idle()
    assert rig.by_n("move_end")[1] == math.ceil((t_a + 0.1) / rig.period - 1e-6)
    assert rig.c.positions(1)["X"] == pytest.approx(x_a + 0.05)


def test_at_0_percent_the_abort_stops_where_the_frozen_axes_stand(rig):
    _slow_move_at(rig, 0)
    x = rig.c.positions(1)["X"]
    reply = rig.cmd("A")
    rig.run_until_idle()
    assert rig.by_n("move_end")[1] == rig.cyc(reply.t_done)
    assert rig.c.positions(1)["X"] == x


def test_a_during_the_i11_delay_discards_the_calculated_lines_and_frees_their_words(rig):
    """``A`` with nothing moving yet (I11 = 500: lines 1-3 calculated at the first RTI, the
    first move due 500 ms after ``R``): the calculated moves are discarded with their words
    (TUM p319), the uncalculated lines stay; no move starts."""
    rig.ok("I11=500")
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM100 TA10 TS0 X1", "X2", "X3", "X4", "X5"])
    assert rig.c.rotary(1)["used_words"] == 8  # 4 words in line 1, one in each other
    rig.ok("R")
    rig.run_for(0.1)
    assert sorted(rig.by_n("line_calculated")) == [1, 2, 3]
    rig.ok("A")
    rig.run_for(1.0)
    assert rig.by_n("move_start") == {}
    assert rig.c.rotary(1)["used_words"] == 2  # X4, X5
    assert rig.c.coord(1)["program"]["state"] == "aborted"


def test_a_during_the_i11_delay_of_a_fixed_program_stops_it(rig):
    """The same with a fixed motion program (``B1``, no rotary buffer): aborted, no move."""
    for cmd in ("I11=500", "OPEN PROG 1", "CLEAR", "TM100 TA10 TS0 X1", "X2", "CLOSE",
                "&1 B1", "R"):
        rig.ok(cmd)
    rig.run_for(0.1)
    rig.ok("A")
    rig.run_for(1.0)
    assert rig.by_n("move_start") == {}
    assert rig.c.coord(1)["program"]["state"] == "aborted"


# -- the ramp itself (lookahead/abort_stop.py) ----------------------------------------------


def _rates(**by_axis: float):
    return lambda axis: by_axis[axis]


def test_the_ramp_each_axis_decelerates_at_its_own_rate_then_stands():
    """X at 10 units/s with 100 units/s² stops after 0.1 s and 0.5 units; Y at -2 units/s with
    0.5 units/s² (a rate below 1) after 4 s and 4 units back; Z (not in ``vel``) and W (at
    rest) stand. Before the abort instant the axes are where ``A`` found them."""
    ramp = abort_stop.plan(1.0, {"Z": 3.0, "X": 0.0, "Y": 1.0, "W": 7.0}, {"X": 10.0, "Y": -2.0,
                           "W": 0.0}, _rates(X=100.0, Y=0.5, Z=100.0, W=100.0))
    assert ramp.t_axis == {"Z": 0.0, "X": pytest.approx(0.1), "Y": pytest.approx(4.0), "W": 0.0}
    assert ramp.t_stop == pytest.approx(4.0)
    assert ramp.positions(0.5) == {"Z": 3.0, "X": 0.0, "Y": 1.0, "W": 7.0}
    mid = ramp.positions(1.05)  # X half-way: 10·0.05 − 100·0.05²/2
    assert mid == {"Z": 3.0, "X": pytest.approx(0.375), "Y": pytest.approx(1.0 - 0.099375),
                   "W": 7.0}
    assert ramp.positions(3.0) == {"Z": 3.0, "X": pytest.approx(0.5), "Y": pytest.approx(-2.0),
                                   "W": 7.0}
    assert ramp.end() == {"Z": 3.0, "X": pytest.approx(0.5), "Y": pytest.approx(-3.0), "W": 7.0}


def test_the_ramp_with_no_rate_or_no_axes_stops_at_once():
    """Ixx15 <= 0 ("never 0", PSRM p73) stops the axis at once ``[INF]``; no axes: no time."""
    ramp = abort_stop.plan(2.0, {"X": 1.0}, {"X": 5.0}, _rates(X=0.0))
    assert ramp.t_axis == {"X": 0.0} and ramp.end() == {"X": 1.0}
    assert abort_stop.plan(2.0, {"X": 1.0}, {"X": 5.0}, _rates(X=-3.0)).t_stop == 0.0
    assert abort_stop.plan(2.0, {}, {}, _rates()).t_stop == 0.0
