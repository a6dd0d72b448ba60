"""Feed-rate and segmentation rules of a coordinate system (issue 37 item 2).

* Isx98, the coordinate system's maximum feedrate (TSRM p193): "If the commanded feedrate is
  greater than Isx98, it will use Isx98 instead"; 0 = no check; TM is not checked.
* With Isx13 > 0 the path of a CIRCLE move is computed as points on the arc every Isx13 ms
  (TSRM p177, spec §9.2): the commanded positions lie on the arc, not on the chord.
* ``/`` and ``\\`` (TUM p217, the table of stop commands; TSRM p177): with Isx13 > 0 ``/``
  stops at the end of the move executing, undoing its blend; ``\\`` is a quick stop in the
  special lookahead and acts as ``H`` outside it; with Isx13 = 0 ``/`` acts as ``Q`` and
  ``\\`` as ``H``.
"""

from __future__ import annotations

import math

import pytest


def _run(rig, lines, *setup):
    for cmd in setup:
        rig.ok(cmd)
    rig.rotary_setup()
    rig.c.load_lines(1, lines)
    rig.ok("R")


def _span_ms(rig, n):
    start, end = rig.by_n("move_start"), rig.by_n("move_end")
    return (end[n] - start[n]) * rig.period * 1000


# -- Isx98 ---------------------------------------------------------------------------------


def test_tsrm_p193_a_feedrate_above_isx98_runs_at_isx98(rig):
    """X0 -> X100 at F2000 with Isx98 = 1000 (the default): 100 ms of travel, as F1000; the
    move from rest takes TM + TA (TA 50 ms)."""
    _run(rig, ["ABS LINEAR TA50 TS0 F2000 X100"])
    rig.run_until_idle()
    assert _span_ms(rig, 1) == pytest.approx(150, abs=rig.period * 1000)
    assert rig.ok("I5189") == "1000"  # the F in force is Isx98's


def test_tsrm_p193_isx98_zero_does_not_check_the_feedrate(rig):
    _run(rig, ["ABS LINEAR TA50 TS0 F2000 X100"], "I5198=0")
    rig.run_until_idle()
    assert _span_ms(rig, 1) == pytest.approx(100, abs=rig.period * 1000)


def test_tsrm_p193_tm_and_a_smaller_f_are_not_capped(rig):
    _run(rig, ["ABS LINEAR TA50 TS0 F500 X100", "TM40 X200"], "I5198=600")
    rig.run_until_idle()
    start = rig.by_n("move_start")
    assert (start[2] - start[1]) * rig.period * 1000 == pytest.approx(
        200 + 25 - 25, abs=rig.period * 1000)  # 100 / 500 s, then TM40 (>= TA)
    assert rig.ok("I5189") == "40"


# -- CIRCLE along the arc with Isx13 > 0 ----------------------------------------------------


def _radii(rig, n, step_s=0.002):
    """(radius from the origin, position) sampled while move ``n`` runs at full speed (between
    its ramps), stepping the virtual clock."""
    out = []
    c = rig.c
    while c.coord_system(1).current is None or c.coord_system(1).current.n < n:
        rig.run_for(step_s)
    m = c.coord_system(1).current
    t_from, t_to = m.b_start + m.ta_in / 2, m.b_end - m.ta / 2
    while c.env.now < t_to:
        if c.env.now >= t_from:
            p = c.positions(1)
            out.append(math.hypot(p["X"], p["Y"]))
        rig.run_for(step_s)
    return out


@pytest.mark.parametrize("circle,end,vec", [
    ("CIRCLE1", "X0 Y-10", "I-10"),   # clockwise quarter, centre vector
    ("CIRCLE2", "X0 Y10", "I-10"),    # counter-clockwise quarter
    ("CIRCLE1", "X0 Y-10", "R10"),    # the R form, short arc
    ("CIRCLE2", "X10 Y0", "I-10"),    # a full circle (same end point)
])
def test_tsrm_p177_a_segmented_circle_moves_on_the_arc(rig, circle, end, vec):
    """Isx13 = 10 ms: from (10, 0) around the origin at F100; every sampled position of the
    arc move lies 10 from the centre (the chord of a quarter passes 7.07 from it)."""
    _run(rig, ["ABS TA20 TS0 X10 Y0 F100", f"{circle} {end} {vec}", "DWELL0"], "I5113=10")
    radii = _radii(rig, 2)
    assert len(radii) > 20
    assert min(radii) == pytest.approx(10.0, abs=1e-6)
    assert max(radii) == pytest.approx(10.0, abs=1e-6)
    rig.run_until_idle()
    p = rig.c.positions(1)
    want = {"X": float(end.split()[0][1:]), "Y": float(end.split()[1][1:])}
    assert p == {"X": pytest.approx(want["X"], abs=1e-9), "Y": pytest.approx(want["Y"],
                                                                                  abs=1e-9)}


def test_tsrm_p177_the_arc_time_is_its_length_over_f(rig):
    """A quarter of radius 10 at F100: 15.7 mm / 100 mm/s; blended between two LINEAR moves
    the arc move starts TA/2 before its start point and hands over TA/2 before its end."""
    _run(rig, ["ABS TA20 TS0 X10 Y0 F100", "CIRCLE1 X0 Y-10 I-10", "LINEAR X-10 Y-10"],
         "I5113=10")
    rig.run_until_idle()
    start = rig.by_n("move_start")
    assert (start[3] - start[2]) * rig.period * 1000 == pytest.approx(
        10 * math.pi / 2 / 100 * 1000, abs=2 * rig.period * 1000)


def test_tsrm_p177_without_segmentation_a_circle_runs_on_the_chord(rig):
    """Isx13 = 0: CIRCLE runs as LINEAR, so half-way it is at the chord's middle."""
    _run(rig, ["ABS TA20 TS0 X10 Y0 F100", "CIRCLE1 X0 Y-10 I-10", "DWELL0"])
    radii = _radii(rig, 2)
    assert min(radii) == pytest.approx(10 / math.sqrt(2), abs=0.05)


def test_tsrm_p442_abs_r_measures_the_centre_from_the_origin(rig):
    """ABS(R): I0 J0 is the origin itself (with INC(R) it would be the start point)."""
    _run(rig, ["ABS TA20 TS0 X10 Y0 F100", "ABS(R) CIRCLE1 X0 Y-10 I0 J0", "DWELL0"],
         "I5113=10")
    radii = _radii(rig, 2)
    assert min(radii) == pytest.approx(10.0, abs=1e-6)
    assert max(radii) == pytest.approx(10.0, abs=1e-6)


def test_tsrm_p442_inc_r_is_the_default_and_takes_the_vector_from_the_start(rig):
    _run(rig, ["ABS TA20 TS0 X10 Y0 F100", "ABS(R)", "INC(R) CIRCLE1 X0 Y-10 I-10 J0",
               "DWELL0"], "I5113=10")
    radii = _radii(rig, 3)
    assert max(radii) == pytest.approx(10.0, abs=1e-6)


# -- / and \ ---------------------------------------------------------------------------------


def test_tum_p217_slash_with_isx13_stops_at_the_end_of_the_executing_move(rig):
    """Three blended 200 ms moves, Isx13 = 10: ``/`` during the first ends it in a stop at
    its programmed point (TA/2 after it), the program is stopped there and the calculated
    second move starts on ``R``."""
    _run(rig, ["INC TA50 TS0 TM200 X10", "X10", "X10"], "I5113=10")
    rig.run_for(0.05)
    rig.ok("/")
    rig.run_for(1.0)
    start, end = rig.by_n("move_start"), rig.by_n("move_end")
    assert list(start) == [1]
    assert (end[1] - start[1]) * rig.period * 1000 == pytest.approx(250, abs=rig.period * 1000)
    assert [f["state"] for _, _, f in rig.events("program")] == ["running", "stopped"]
    assert rig.c.positions(1) == {"X": pytest.approx(10.0)}
    rig.ok("R")
    rig.run_until_idle()
    assert rig.c.positions(1) == {"X": pytest.approx(30.0)}
    assert sorted(rig.by_n("move_start")) == [1, 2, 3]


def test_tum_p217_slash_in_a_fixed_program_resumes_with_the_calculated_move_not_the_top(rig):
    """PROG 4 of two moves, both calculated when ``/`` comes: ``R`` runs the second one (the
    program has not ended), not the program again from its top."""
    rig.ok("I5113=10")
    rig.ok("OPEN PROG 4 CLEAR")
    rig.ok("INC TA50 TS0 TM200 X10")
    rig.ok("X10")
    rig.ok("CLOSE")
    rig.ok("&1 B4 R")
    rig.run_for(0.05)
    rig.ok("/")
    rig.run_for(1.0)
    assert rig.c.positions(1) == {"X": pytest.approx(10.0)}
    rig.ok("R")
    rig.run_until_idle()
    assert rig.c.positions(1) == {"X": pytest.approx(20.0)}
    assert [f["n"] for _, _, f in rig.events("move_start")] == [1, 2]
    assert [f["state"] for _, _, f in rig.events("program")] == [
        "running", "stopped", "running", "stopped"]


def test_pointing_the_cs_elsewhere_after_slash_drops_the_kept_moves(rig):
    """After ``/`` the calculated moves wait for ``R``; ``B{n}`` points the CS at another
    program, whose moves alone then run [INF]."""
    rig.ok("I5113=10")
    rig.ok("OPEN PROG 5 CLEAR")
    rig.ok("INC TA50 TS0 TM200 Y1")
    rig.ok("CLOSE")
    _run(rig, ["INC TA50 TS0 TM200 X10", "X10", "X10"])
    rig.run_for(0.05)
    rig.ok("/")
    rig.run_for(1.0)
    rig.ok("B5 R")
    rig.run_until_idle()
    assert rig.c.positions(1) == {"X": pytest.approx(10.0), "Y": pytest.approx(1.0)}


def test_tsrm_p177_slash_with_isx13_zero_acts_as_q(rig):
    """Isx13 = 0: ``/`` finishes the calculated moves (two ahead) like ``Q``."""
    _run(rig, ["INC TA50 TS0 TM200 X10", "X10", "X10", "X10", "X10"])
    rig.run_for(0.05)
    rig.ok("/")
    rig.run_until_idle()
    assert rig.c.positions(1) == {"X": pytest.approx(30.0)}  # as test of Q: the 3 calculated
    assert [f["state"] for _, _, f in rig.events("program")] == ["running", "stopped"]


@pytest.mark.parametrize("isx13", [0, 10])
def test_tsrm_p177_backslash_outside_lookahead_acts_as_h(make_rig, isx13):
    """``\\`` without the special lookahead is a feed hold: ``%`` slews to 0 at Isx95 and
    ``R`` resumes; with ``H`` instead the same log."""
    logs = []
    for cmd in ("\\", "H"):
        rig = make_rig()
        _run(rig, ["INC TA50 TS0 TM500 X10"], f"I5113={isx13}")
        rig.run_for(0.1)
        rig.ok(cmd)
        rig.run_for(2.0)
        assert rig.ok("%") == "0"
        rig.ok("R")
        rig.run_until_idle()
        logs.append(rig.events())
    assert logs[0] == logs[1]


def test_tsrm_p181_backslash_in_the_special_lookahead_is_not_simulated(rig):
    """With Isx13 > 0, Isx20 > 0 and DEFINE LOOKAHEAD the quick stop is valid but not
    simulated: its own message, and nothing changes (the move runs on)."""
    rig.ok("&1 #1->1000X")
    rig.ok("I5120=10")
    rig.ok("&1 DEFINE LOOKAHEAD 50,10")
    _run(rig, ["INC TA50 TS0 TM200 X10"], "I5113=10")
    rig.run_for(0.05)
    r = rig.cmd("\\")
    assert r.error is not None and "ERR003" in str(r.error)
    assert r.detail[0] == "not_simulated" and "quick stop" in r.detail[1]
    rig.run_until_idle()
    assert rig.c.positions(1) == {"X": pytest.approx(10.0)}
