"""Kinematic coordinate systems (issue 24 item 1; sim/pmac/kinematics): OPEN FORWARD /
OPEN INVERSE buffers, ``#n->I``, Isx50, when each program runs, segment-by-segment motor
positions, and the run-time error of an inverse that cannot be computed. Virtual time."""

from __future__ import annotations

import pytest

# A two-jack table (our own, in the style of Diamond's CS_2jack): X height, Y pitch (mm
# difference); 1000 counts per mm.
FORWARD = ["Q7=(P1+P2)/2000", "Q8=(P2-P1)/1000"]
INVERSE = ["P1=(Q7-Q8/2)*1000", "P2=(Q7+Q8/2)*1000"]


def _kinematic_cs(rig, inverse=INVERSE, isx13=10):
    rig.ok("&1 #1->I #2->I")
    rig.ok("&1 OPEN FORWARD CLEAR")
    for line in FORWARD:
        rig.ok(line)
    rig.ok("CLOSE")
    rig.ok("&1 OPEN INVERSE CLEAR")
    for line in inverse:
        rig.ok(line)
    rig.ok("CLOSE")
    rig.ok(f"I5150=1 I5113={isx13}")


def _program(rig, *lines):
    rig.ok("OPEN PROG 1 CLEAR")
    for line in lines:
        rig.ok(line)
    rig.ok("CLOSE")


def _err(rig, line):
    reply = rig.cmd(line)
    assert reply.error is not None, line
    return str(reply.error)


def test_tsrm_p379_open_forward_and_inverse_are_stored_listed_and_cleared(rig):
    _kinematic_cs(rig)
    assert rig.ok("&1 LIST FORWARD") == "Q7=(P1+P2)/2000\rQ8=(P2-P1)/1000\rRET"
    assert rig.ok("&1 LIST INVERSE").split("\r")[0] == "P1=(Q7-Q8/2)*1000"
    assert rig.ok("&2 LIST FORWARD") == ""  # one buffer per CS: CS 2's is empty
    assert "ERR003" in _err(rig, "&1 LIST FORWARD,9,1")  # beyond the last line
    rig.ok("&1 OPEN FWD CLEAR")
    rig.ok("CLOSE")
    assert rig.ok("&1 LIST FORWARD") == ""  # cleared: nothing to list


def test_tsrm_p379_open_forward_refused_with_a_buffer_open_or_a_program_running(rig):
    port = rig.c.open_port("other")
    rig.ok("OPEN PROG 2", port)
    assert "ERR007" in _err(rig, "&1 OPEN FORWARD")
    rig.ok("CLOSE", port)
    _program(rig, "LINEAR INC TA10 TS0 TM2000 X1")
    rig.ok("&2 #3->1000X")
    rig.ok("&2 B1 R")
    assert "ERR001" in _err(rig, "&1 OPEN INVERSE")


def test_tsrm_p379_no_program_may_start_while_a_kinematic_buffer_is_open(rig):
    _program(rig, "LINEAR INC TA10 TS0 TM100 X1")
    rig.ok("&1 #3->1000X B1")
    port = rig.c.open_port("editor")
    rig.ok("&1 OPEN INVERSE", port)
    assert "ERR015" in _err(rig, "&1 R")
    rig.ok("CLOSE", port)


def test_tsrm_p270_n_arrow_i_reports_i(rig):
    rig.ok("&1 #4->I")
    assert rig.ok("&1 #4->") == "I"


def test_tum_p267_pmatch_runs_the_forward_program_and_the_motors_stay(rig):
    _kinematic_cs(rig)
    rig.ok("#1J=1000 #2J=3000")
    rig.run_for(3.0)
    since = rig.c.log.last_seq
    rig.ok("&1 PMATCH")
    assert rig.ok("&1 Q7 Q8") == "2\r2"
    assert rig.ok("#1P #2P") == "1000\r3000"
    ev = rig.events("pmatch", since=since)
    assert ev[0][2]["axes"] == {"X": 2.0, "Y": 2.0}


def test_tum_p259_pmatch_without_kinematics_inverts_the_axis_definitions(rig):
    rig.ok("&1 #3->500Z")
    rig.ok("#3J=1500")
    rig.run_for(3.0)
    rig.ok("&1 PMATCH")
    assert rig.c.positions(1)["Z"] == 3.0
    assert rig.ok("#3P") == "1500"


def test_tsrm_p181_isx50_forward_runs_on_r_and_moves_go_through_the_inverse(rig):
    _kinematic_cs(rig)
    rig.ok("#1J=1000 #2J=3000")
    rig.run_for(3.0)
    _program(rig, "LINEAR ABS TA100 TS0 TM1000 X3 Y-1")
    since = rig.c.log.last_seq
    rig.ok("&1 B1 R")
    rig.run_until_idle()
    kinds = [e[1] for e in rig.events("pmatch", "move_start", since=since)]
    assert kinds[:2] == ["pmatch", "move_start"]  # the forward program ran at R
    # end: X=3, Y=-1 -> P1 = (3+0.5)*1000, P2 = (3-0.5)*1000
    assert rig.ok("#1P #2P") == "3500\r2500"
    assert rig.ok("&1 Q7 Q8") == "3\r-1"


def test_tum_p258_motors_follow_the_inverse_every_isx13_segment(rig):
    """Between two segment instants a motor moves in a straight line between the inverse
    results there; at each instant the forward program of the motor positions gives the
    axis positions (the two agree through the forward kinematics)."""
    _kinematic_cs(rig, inverse=["P1=Q7*Q7*1000", "P2=(Q7+Q8)*1000"], isx13=10)
    rig.ok("&1 OPEN FORWARD CLEAR")
    rig.ok("Q7=SQRT(P1/1000) Q8=P2/1000-Q7")
    rig.ok("CLOSE")
    rig.ok("&1 PMATCH")
    _program(rig, "LINEAR ABS TA50 TS0 TM400 X2 Y1")
    rig.ok("&1 B1 R")
    c = rig.c
    rig.run_for(0.25)
    start = [e for e in rig.events("move_start")][0][0] * rig.period
    seg_t0 = c.coord_system(1)._seg_t0
    assert seg_t0 == pytest.approx(start)
    for k in (3, 7, 12):
        t = seg_t0 + k * 0.010
        x = c.positions(1, t)["X"]
        assert c.motor_position(1, t) == pytest.approx(x * x * 1000, rel=1e-12)
        mid = t + 0.005
        x2 = c.positions(1, t + 0.010)["X"]
        assert c.motor_position(1, mid) == pytest.approx(
            (x * x + x2 * x2) / 2 * 1000, rel=1e-12)
        assert c.motor_position(1, mid) != pytest.approx(
            c.positions(1, mid)["X"] ** 2 * 1000, rel=1e-9)  # not the exact curve: segments
    rig.run_until_idle()
    assert c.motor_position(1, c.env.now) == pytest.approx(4000)
    rig.ok("&1 PMATCH")
    assert rig.ok("&1 Q7 Q8") == "2\r1"


@pytest.mark.parametrize("inverse, why", [
    (["P1=(Q7-Q8/2)*1000"], "P2 was not set"),
    (["P1=(Q7-Q8/2)*1000", "P2=Q7/(Q8-Q8)"], "P2 = "),
])
def test_tum_p265_an_inverse_without_a_result_is_a_run_time_error(rig, inverse, why):
    """No valid motor position from the inverse program: the program stops with the
    run-time error (``??`` word 2 bit 22); the outputs keep their last good values."""
    _kinematic_cs(rig, inverse=inverse)
    _program(rig, "LINEAR ABS TA100 TS0 TM500 X1 Y1")
    since = rig.c.log.last_seq
    rig.ok("&1 B1 R")
    rig.run_until_idle()
    ev = rig.events("kinematics", "program", since=since)
    kin = [e for e in ev if e[1] == "kinematics"]
    assert why in kin[0][2]["error"]
    aborted = [e for e in ev if e[1] == "program" and e[2].get("state") == "aborted"]
    assert aborted and aborted[0][2]["error"] == "run_time_error"
    assert aborted[0][0] == kin[0][0]  # at once, the servo cycle the move would start
    w2 = int(rig.ok("&1 ??")[6:12], 16)
    assert w2 & (1 << 22)
    # P1, P2 hold what the forward program got at R (the motor counts, 0): the failed
    # inverse's partial output (P1 = 500) was undone; the motors never moved
    assert rig.ok("P1 P2") == "0\r0"
    assert rig.ok("#1P #2P") == "0\r0"


def test_tum_p265_an_inverse_loop_that_never_ends_is_a_run_time_error(rig):
    """WHILE loops are allowed in an inverse program (iterative solutions); one that never
    ends stops the program with the run-time error instead of hanging the card."""
    _kinematic_cs(rig, inverse=["P1=(Q7-Q8/2)*1000", "P2=(Q7+Q8/2)*1000",
                                "WHILE (Q7 > -1000)", "Q40=Q40+1", "ENDWHILE"])
    _program(rig, "LINEAR ABS TA100 TS0 TM500 X1 Y1")
    since = rig.c.log.last_seq
    rig.ok("&1 B1 R")
    rig.run_until_idle()
    kin = rig.events("kinematics", since=since)
    assert "no end after" in kin[0][2]["error"]
    assert rig.c.coord_system(1).run_time_error
    assert rig.ok("#1P #2P") == "0\r0"


def test_tum_p265_an_iterative_inverse_drives_the_motors(rig):
    _kinematic_cs(rig, inverse=[
        "Q61=Q7 Q62=0",
        "WHILE (Q62 < 30)",
        "Q61=Q61-(Q61*Q61*Q61-Q7)/(3*Q61*Q61)",
        "Q62=Q62+1",
        "ENDWHILE",
        "P1=Q61*1000 P2=Q8*1000",
    ])
    rig.ok("&1 OPEN FORWARD CLEAR")
    rig.ok("Q7=(P1/1000)*(P1/1000)*(P1/1000) Q8=P2/1000")
    rig.ok("CLOSE")
    rig.ok("#1J=1000")
    rig.run_for(3.0)
    _program(rig, "LINEAR ABS TA100 TS0 TM500 X8 Y2")
    rig.ok("&1 B1 R")
    rig.run_until_idle()
    assert rig.ok("#1P #2P") == "2000\r2000"  # cube root of 8, in counts


def _one_motor_cs(rig, cs, motor, counts_per_unit):
    """CS ``cs``: motor ``motor`` (``#n->I``) at ``counts_per_unit`` x X (TSRM p181 Isx50)."""
    rig.ok(f"&{cs} #{motor}->I")
    rig.ok(f"&{cs} OPEN FORWARD CLEAR")
    rig.ok(f"Q7=P{motor}/{counts_per_unit}")
    rig.ok("CLOSE")
    rig.ok(f"&{cs} OPEN INVERSE CLEAR")
    rig.ok(f"P{motor}=Q7*{counts_per_unit}")
    rig.ok("CLOSE")
    rig.ok(f"I5{cs}50=1 I5{cs}13=10")


def test_two_kinematic_cs_each_hold_their_own_motors_at_rest(rig):
    """Each CS's inverse program gives the positions of its own ``#n->I`` motors (TUM p262):
    CS 1 drives motor 2, CS 2 motor 1; at rest both sit where their own inverse puts them."""
    _one_motor_cs(rig, 1, 2, 1000)
    _one_motor_cs(rig, 2, 1, 2000)
    _program(rig, "LINEAR ABS TA10 TS0 TM200 X2")
    rig.ok("OPEN PROG 2 CLEAR")
    rig.ok("LINEAR ABS TA10 TS0 TM300 X3")
    rig.ok("CLOSE")
    rig.ok("&1 B1 R &2 B2 R")
    rig.run_for(1.0)
    assert rig.ok("#1P #2P") == "6000\r2000"


def _position_after_a_blend_start(rig, ask_before):
    """Motor 1's reported position a little after the third move of a blended sequence
    starts (inside the Isx13 segment it starts in), asked before that start too or not."""
    _one_motor_cs(rig, 1, 1, 1000)
    _program(rig, "LINEAR ABS TA10 TS0 TM205", "X2", "X-1", "X3")
    rig.ok("&1 B1 R")
    rig.c.env.run(until=0.2105)
    if ask_before:
        rig.ok("#1P")
    rig.c.env.run(until=0.2155)
    reply = rig.cmd("#1P")
    (start,) = [k for k, _, f in rig.events("move_start") if f["n"] == 3]
    assert 0.2105 < start * rig.period < reply.t_done  # between the two questions
    return reply.reply


def test_tum_p265_a_segment_a_move_starts_in_interpolates_from_the_path_executed(make_rig):
    """With Isx13 > 0 the inverse runs at each segment instant of the path executed then and
    the motors are interpolated in between (TUM p265; spec §12.6 ``[INF]`` linearly). A move
    (``X-1``, 205 ms moves, 10 ms segments) that starts inside a segment does not change the
    segment's first instant, which lay on the move before: 1902.45 counts there, 1969.51 at
    the next instant (the blend into ``X-1``), 1953.6 at 0.2156 s — whether or not the
    position was asked before the move started (a report never changes a later one)."""
    assert _position_after_a_blend_start(make_rig(), ask_before=False) == "1953.6"
    assert _position_after_a_blend_start(make_rig(), ask_before=True) == "1953.6"
