"""``??`` coordinate-system status, word 2 move-mode bits (4, 1, 0) (TSRM p286-287; PSRM
p195; spec §9.4): LINEAR 000, RAPID 010, CIRCLE1 001, CIRCLE2 011, SPLINE 101, PVT 110 — the
mode last calculated from the program."""

from __future__ import annotations

import pytest


@pytest.mark.parametrize(
    ("statement", "bits"),
    [
        ("LINEAR", (0, 0, 0)),
        ("RAPID", (0, 1, 0)),
        ("CIRCLE1", (0, 0, 1)),
        ("CIRCLE2", (0, 1, 1)),
        ("SPLINE1", (1, 0, 1)),
        ("SPLINE2", (1, 0, 1)),
        ("PVT100", (1, 1, 0)),
    ],
)
def test_tsrm_p286_word2_bits_4_1_0_show_the_move_mode(rig, statement, bits):
    rig.rotary_setup()
    rig.c.load_lines(1, [statement])
    rig.ok("R")
    rig.run_for(0.02)
    w2 = int(rig.ok("??")[6:12], 16)
    assert (w2 >> 4 & 1, w2 >> 1 & 1, w2 & 1) == bits
    assert w2 >> 2 & 0b11 == 0  # bits 2 and 3 belong to no mode


def test_tsrm_p286_a_fresh_card_reports_linear_mode(rig):
    """Power-up: LINEAR is the default move mode (TSRM p442)."""
    w2 = int(rig.ok("??")[6:12], 16)
    assert w2 & 0b10011 == 0


def _words(rig) -> tuple[set[int], set[int]]:
    reply = rig.ok("??")
    w1, w2 = int(reply[:6], 16), int(reply[6:12], 16)
    return {i for i in range(24) if w1 >> i & 1}, {i for i in range(24) if w2 >> i & 1}


def _start(rig, lines, command="R", setup=()):
    rig.rotary_setup()
    for s in setup:
        rig.ok(s)
    rig.c.load_lines(1, lines)
    rig.ok(command)
    rig.run_for(0.05)


def test_tsrm_p285_word1_of_a_running_blended_time_mode_sequence(rig):
    """Word 1: bit 0 running a program, bit 2 continuous motion mode (a blended move
    executing), bit 3 move specified by time (TM), bit 4 continuous motion request (after
    ``R``); word 2 bit 17 (in position) is clear while a move executes."""
    w1, w2 = _words(rig)
    assert w1 == set() and 17 in w2  # idle: nothing running, in position
    _start(rig, ["TM500 TA100 TS0 X10", "X20", "X30"])
    w1, w2 = _words(rig)
    assert w1 == {0, 2, 3, 4}
    assert 17 not in w2


def test_tsrm_p285_word1_bit3_is_clear_in_feedrate_mode(rig):
    _start(rig, ["F100 TA100 TS0 X10", "X20"])
    assert _words(rig)[0] == {0, 2, 4}


def test_tsrm_p285_single_step_sets_bit1_and_clears_the_continuous_motion_request(rig):
    """``S``: bit 1 single-step mode, bit 4 (continuous motion request) 0; once the step is
    done the program is stopped (bit 0 clear) and in position."""
    _start(rig, ["TM500 TA100 TS0 X10", "X20"], command="S")
    w1, _ = _words(rig)
    assert {0, 1} <= w1 and 4 not in w1
    rig.run_until_idle()
    w1, w2 = _words(rig)
    assert w1 & {0, 1, 2, 4} == set() and 17 in w2


def test_tsrm_p190_isx92_1_at_r_clears_the_continuous_motion_request(rig):
    _start(rig, ["TM500 TA100 TS0 X10", "X20"], setup=["I5192=1"])
    w1, _ = _words(rig)
    assert 0 in w1 and 4 not in w1


def test_tsrm_p285_a_rapid_move_is_not_continuous_motion_mode(rig):
    """RAPID is never blended (TUM p286): bit 2 stays clear while it runs; word 2 shows the
    RAPID mode bits (010)."""
    _start(rig, ["RAPID X10"])
    w1, w2 = _words(rig)
    assert w1 == {0, 4}
    assert w2 & {0, 1, 4} == {1} and 17 not in w2
