"""Kinematic coordinate systems, what the engine keeps between positions asked: the Isx13
segmentation as last written, each CS's own ``#n->I`` motors (TSRM p181-182 Isx50 / Isx13,
p270 ``#n->I``; TUM p262-265: the inverse program turns the CS's axis positions into the
positions of its ``#n->I`` motors, the forward program gets the positions of its motors).
Virtual time; positions asked through the terminal (``#nP``)."""

from __future__ import annotations

import math

import pytest


def _cs(rig, cs, forward, inverse, motors):
    for n, definition in motors.items():
        rig.ok(f"&{cs} #{n}->{definition}")
    rig.ok(f"&{cs} OPEN FORWARD CLEAR")
    for line in forward:
        rig.ok(line)
    rig.ok("CLOSE")
    rig.ok(f"&{cs} OPEN INVERSE CLEAR")
    for line in inverse:
        rig.ok(line)
    rig.ok("CLOSE")
    rig.ok(f"I5{cs}50=1 I5{cs}13=10")


def _program(rig, n, *lines):
    rig.ok(f"OPEN PROG {n} CLEAR")
    for line in lines:
        rig.ok(line)
    rig.ok("CLOSE")


def _squared(rig, isx13_later):
    """Motor 1 = 1000 X² counts; X to 2 in 200 ms; Isx13 written to ``isx13_later`` (or
    not) at 0.1 s; motor 1 and X at 0.1555 s."""
    _cs(rig, 1, ["Q7=SQRT(P1/1000)"], ["P1=Q7*Q7*1000"], {1: "I"})
    _program(rig, 1, "LINEAR ABS TA10 TS0 TM200", "X2")
    rig.ok("&1 B1 R")
    rig.c.env.run(until=0.1)
    rig.ok("#1P")
    if isx13_later is not None:
        rig.ok(f"I5113={isx13_later}")
    rig.c.env.run(until=0.1555)
    reply = rig.cmd("#1P")
    return float(reply.reply), rig.c.positions(1)["X"]


def test_tsrm_p175_isx13_written_during_a_move_changes_how_the_motors_are_interpolated(
        make_rig):
    """Isx13 = 10 ms: between segment instants the motor is interpolated (2079.9 counts,
    above 1000 X² on the curve); Isx13 written 0 while the move runs: the inverse is
    evaluated at the instant itself from then on (TSRM p175; the engine's docstring)."""
    segmented, x = _squared(make_rig(), None)
    assert segmented == 2079.9 and abs(1000 * x * x - 2079.15) < 0.01
    exact, x = _squared(make_rig(), 0)
    assert exact == round(1000 * x * x, 1) == 2079.2


def test_tum_p262_each_cs_has_its_own_inverse_motors_and_axis_motors_beside_them(rig):
    """CS 1: motor 1 ``#1->I`` (1000 counts / X), motor 3 ``#3->1000Z`` and motor 4 ``#4->Y``
    defined as usual beside it; CS 2: motor 2 ``#2->I`` (2000 counts / X). Only the ``#n->I``
    motors of a CS take its inverse program's P-variables; the others follow their axis
    definitions; at rest each motor sits where its own CS put it."""
    _cs(rig, 1, ["Q7=P1/1000"], ["P1=Q7*1000"], {1: "I", 3: "1000Z", 4: "Y"})
    _cs(rig, 2, ["Q7=P2/2000"], ["P2=Q7*2000"], {2: "I"})
    _program(rig, 1, "LINEAR ABS TA10 TS0 TM200 X2 Y3 Z1")
    _program(rig, 2, "LINEAR ABS TA10 TS0 TM300 X3")
    rig.ok("&1 B1 R &2 B2 R")
    rig.run_for(1.0)
    assert rig.events("kinematics") == []  # no inverse failed
    assert rig.ok("#1P #2P #3P #4P") == "2000\r6000\r1000\r3"


def test_tum_p262_pmatch_gives_the_forward_program_only_its_own_cs_motors(rig):
    """The forward program of CS 1 gets the positions of CS 1's motors in P1..: a P-variable
    numbered as a motor of another CS keeps its value (CS 2's motor 2, P2 = 42)."""
    _cs(rig, 1, ["Q7=P1/1000"], ["P1=Q7*1000"], {1: "I"})
    _cs(rig, 2, ["Q7=P2/2000"], ["P2=Q7*2000"], {2: "I"})
    rig.ok("#1J=1000 #2J=4000")
    rig.run_for(3.0)
    rig.ok("P1=0 P2=42")
    rig.ok("&1 PMATCH")
    assert rig.ok("&1 Q7 P1 P2") == "1\r1000\r42"
    rig.ok("P1=7 P2=0")
    rig.ok("&2 PMATCH")
    assert rig.ok("&2 Q7 P1 P2") == "2\r7\r4000"


def test_tsrm_p270_a_motor_made_n_arrow_i_later_follows_the_inverse_from_then_on(rig):
    """``#2->I`` written after the CS has already run its inverse program: motor 2 is one of
    its ``#n->I`` motors from then on (the new inverse program sets P2 as well)."""
    _cs(rig, 1, ["Q7=P1/1000"], ["P1=Q7*1000"], {1: "I"})
    _program(rig, 1, "LINEAR ABS TA10 TS0 TM200 X2")
    rig.ok("&1 B1 R")
    rig.run_for(1.0)
    assert rig.ok("#1P") == "2000"
    rig.ok("&1 #2->I")
    rig.ok("&1 OPEN INVERSE CLEAR")
    rig.ok("P1=Q7*1000 P2=Q7*500")
    rig.ok("CLOSE")
    _program(rig, 1, "LINEAR ABS TA10 TS0 TM200 X4")
    rig.ok("&1 B1 R")
    rig.run_for(1.0)
    assert rig.events("kinematics") == []
    assert rig.ok("#1P #2P") == "4000\r2000"


def test_tsrm_p175_isx13_0_blended_moves_take_the_inverse_at_each_instant(rig):
    """Isx13 = 0: no segmentation; blended moves in a kinematic CS run and motor 1 is the
    inverse of X at the instant itself, through every move start."""
    _cs(rig, 1, ["Q7=P1/1000"], ["P1=Q7*1000"], {1: "I"})
    rig.ok("I5113=0")
    _program(rig, 1, "LINEAR ABS TA10 TS0 TM205", "X2", "X-1", "X3")
    rig.ok("&1 B1 R")
    for t in (0.1, 0.2155, 0.4, 0.5):
        rig.c.env.run(until=t)
        reply = rig.cmd("#1P")
        assert float(reply.reply) == round(1000 * rig.c.positions(1)["X"], 1)
    rig.run_for(1.0)
    assert rig.events("kinematics") == [] and rig.ok("#1P") == "3000"


def _late_blend_start(make_rig, ask_before):
    """test_kinematics' 1953.6-count case with the program started at 1 s: motor 1 asked
    inside the 10 ms segment the third move starts in, after that start (and before it, if
    ``ask_before``); the instants from a first run."""

    def run(asks):
        rig = make_rig()
        _cs(rig, 1, ["Q7=P1/1000"], ["P1=Q7*1000"], {1: "I"})
        _program(rig, 1, "LINEAR ABS TA10 TS0 TM205", "X2", "X-1", "X3")
        rig.c.env.run(until=1.0)
        rig.ok("&1 B1 R")
        replies = []
        for t in asks:
            rig.c.env.run(until=t)
            replies.append(rig.cmd("#1P"))
        (start,) = [k * rig.period for k, _, f in rig.events("move_start") if f["n"] == 3]
        return rig.c.coord_systems[1]._seg_t0, start, replies

    t0, start, _ = run([1.5])
    seg = t0 + math.floor((start - t0) / 0.01) * 0.01
    before, after = (seg + start) / 2, (start + seg + 0.01) / 2
    *_, replies = run([before, after] if ask_before else [after])
    assert start < replies[-1].t_done < seg + 0.01
    return replies[-1].reply


def test_tum_p265_a_move_starting_in_a_segment_after_the_first_second_interpolates_too(
        make_rig):
    """The segment a move starts in interpolates from the path executed at any instant of
    the run (here after 1 s), asked before the move started or not."""
    assert _late_blend_start(make_rig, False) == _late_blend_start(make_rig, True)


@pytest.mark.parametrize(("p1", "fails"), [
    ("140737488355327", False), ("99999999999999", False), ("-140737488355327", False),
    ("140737488355328", True), ("-140737488355328", True), ("281474976710656", True),
    ("-281474976710656", True),
])
def test_tum_p265_an_inverse_result_at_or_beyond_2_to_the_47_is_a_run_time_error(
        rig, p1, fails):
    """A motor position of magnitude 2^47 counts or more is saturated, not a position: the
    program stops with the run-time error; just below it is a position (the engine's
    docstring, ``|Pn| >= 2**47``)."""
    _cs(rig, 1, ["Q7=P1/1000"], [f"P1={p1}"], {1: "I"})
    _program(rig, 1, "LINEAR ABS TA10 TS0 TM200 X2")
    rig.ok("&1 B1 R")
    rig.run_for(0.5)
    errors = [f["error"] for _, _, f in rig.events("kinematics")]
    assert bool(errors) == fails, errors
    if fails:
        assert "P1 = " in errors[0]


def test_tum_p259_pmatch_without_kinematics_inverts_each_axis_definition(rig):
    """Isx50 = 0: PMATCH inverts the axis definitions, axis = (motor - offset) / scale
    (TUM p259, p267): ``#3->500Z+200`` at 1450 counts is Z 2.5; ``#4->-1X`` at 3 is X -3;
    ``#5->Y`` (scale 1) at 7 is Y 7; a ``#6->I`` motor, with kinematics off, sets no axis."""
    rig.ok("&1 #3->500Z+200 #4->-1X #5->Y #6->I")
    rig.ok("I5150=0")
    rig.ok("#3J=1450 #4J=3 #5J=7")
    rig.run_for(3.0)
    assert rig.ok("#3P #4P #5P") == "1450\r3\r7"
    rig.ok("&1 PMATCH")
    (pmatch,) = rig.events("pmatch")
    assert pmatch[2]["axes"] == {"Z": 2.5, "X": -3.0, "Y": 7.0}
    assert rig.ok("#3P #4P #5P") == "1450\r3\r7"  # the motors stay where they are


def test_tum_p265_another_cs_asked_meanwhile_does_not_change_the_segment_a_move_starts_in(
        make_rig):
    """A move of CS 1 starting inside a segment (as test_kinematics' 1953.6-count case), with
    a second kinematic CS at rest asked between that start and CS 1's question: CS 1's answer
    is the one it gets with nobody asking in between (its segment interpolates from the path
    executed)."""

    def run(asks):
        rig = make_rig()
        _cs(rig, 1, ["Q7=P1/1000"], ["P1=Q7*1000"], {1: "I"})
        _cs(rig, 2, ["Q7=P2/2000"], ["P2=Q7*2000"], {2: "I"})
        _program(rig, 1, "LINEAR ABS TA10 TS0 TM205", "X2", "X-1", "X3")
        rig.ok("&2 PMATCH")  # CS 2's axes from its motors: its inverse drives them now
        rig.ok("&1 B1 R")
        replies = []
        for t, question in asks:
            rig.c.env.run(until=t)
            replies.append(rig.cmd(question))
        (start,) = [k * rig.period for k, _, f in rig.events("move_start") if f["n"] == 3]
        t0 = rig.c.coord_systems[1]._seg_t0
        return start, t0 + math.floor((start - t0) / 0.01) * 0.01, replies

    start, seg, _ = run([(0.5, "#1P")])
    t_cs2, t_cs1 = start + (seg + 0.01 - start) / 3, start + 2 * (seg + 0.01 - start) / 3
    _, _, (cs2, alone) = run([(t_cs2, "#2P"), (t_cs1, "#1P")])
    assert cs2.reply == "0" and start < cs2.t_done < alone.t_done < seg + 0.01
    _, _, (asked,) = run([(t_cs1, "#1P")])
    assert asked.t_done == alone.t_done and asked.reply == alone.reply
