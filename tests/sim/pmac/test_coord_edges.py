"""Edges of the coordinate system's settings, pinned to the manual: planning at RTIs of an
odd I8 (TUM p236) and a PVT segment time over one second (TSRM p463). Times are servo
cycles.
"""

from __future__ import annotations

import math

import pytest


def _start(rig, lines: list[str]) -> None:
    rig.rotary_setup()
    rig.c.load_lines(1, lines)
    rig.ok("R")


def test_an_odd_i8_plans_after_each_move_start_at_the_next_rti_every_i8_plus_1_cycles(make_rig):
    """TUM p236: RTIs come every I8+1 servo cycles, and a move start asks for planning at the
    next one. I8 = 3: every 4th cycle, so the line planned after move 2 (line 4) and after
    move 3 (line 5) are calculated at the first multiple of 4 after that move's start."""
    rig = make_rig(i8=3)
    _start(rig, ["TM100 TA10 TS0 X1", "X2", "X3", "X4", "X5"])
    rig.run_until_idle()
    starts, calc = rig.by_n("move_start"), rig.by_n("line_calculated")
    assert calc[4] == (starts[2] // 4 + 1) * 4
    assert calc[5] == (starts[3] // 4 + 1) * 4
    assert rig.c.positions(1) == {"X": 5.0}


def test_pvt_segments_of_more_than_a_second_each_take_their_time(rig):
    """TSRM p463: ``PVT{t}`` sets the segment time (up to 4095.9998 ms); ``PVT1500``: three
    segments of constant lines each last 1.5 s, abutting, and end at their points."""
    _start(rig, ["ABS PVT1500 X10:0", "X20:0", "X30:0"])
    rig.run_until_idle()
    starts, ends = rig.by_n("move_start"), rig.by_n("move_end")
    t0 = starts[1] * rig.period
    for n in (1, 2, 3):
        assert ends[n] == math.ceil((t0 + 1.5 * n) / rig.period - 1e-6)
    assert starts[2] == ends[1] and starts[3] == ends[2]
    assert rig.c.positions(1) == {"X": pytest.approx(30.0)}


def test_segmentation_mode_a_ta_line_after_the_last_move_sets_its_final_deceleration(make_rig):
    """Spec §9.1 (PUM p175): the final deceleration uses the TA in force after the last move
    line. Isx13 > 0: ``TA50`` arrives while ``TM500 TA100`` runs, before its deceleration
    point; the move stops in 50 + 500 + 25 ms (not + 50 ms)."""
    rig = make_rig(i5113=10)
    _start(rig, ["TM500 TA100 TS0 X10"])
    rig.run_for(0.2)
    rig.c.load_lines(1, ["TA50"])
    rig.run_until_idle()
    starts, ends = rig.by_n("move_start"), rig.by_n("move_end")
    assert ends[1] - starts[1] == math.ceil(rig.ms_cycles(50 + 500 + 25) - 1e-6)
    assert rig.c.positions(1) == {"X": 10.0}


def _word2_bits(rig) -> set[int]:
    w2 = int(rig.ok("??")[6:12], 16)
    return {i for i in range(24) if w2 >> i & 1}


def test_word2_bit12_is_set_while_a_dwell_executes_and_only_then(rig):
    """PSRM p195 ``??`` word 2 bit 12 (dwell move) ``[INF]`` set while a DWELL executes: in
    the dwell after a LINEAR move it is the only bit of word 2 (LINEAR mode 000, not in
    position), and clear again once motion has ended."""
    _start(rig, ["TM100 TA10 TS0 X5", "DWELL500", "X10"])
    rig.run_for(0.3)
    assert rig.c.coord(1)["program"]["line"] == 2
    assert _word2_bits(rig) == {12}
    rig.run_until_idle()
    assert 12 not in _word2_bits(rig)


def test_word2_bit12_is_clear_during_a_pvt_move(rig):
    """PSRM p195: no DWELL, no bit 12; word 2 shows only the PVT mode bits 4 and 1 (110)."""
    _start(rig, ["ABS PVT200 X10:100", "X20:0"])
    rig.run_for(0.3)
    assert rig.c.coord(1)["program"]["line"] == 2
    assert _word2_bits(rig) == {4, 1}


def test_q_during_the_last_calculated_move_stops_the_program_at_that_moves_end(rig):
    """TUM p319 ``Q``: calculation stops, the moves already calculated are finished, and only
    then is the program stopped. ``Q`` half-way through the only move: the ``stopped`` program
    event comes at the move's ``move_end`` cycle, and the move reaches its end point."""
    _start(rig, ["TM1000 TA10 TS0 X10"])
    rig.run_for(0.5)
    q_time = rig.c.env.now
    rig.ok("Q")
    rig.run_until_idle()
    stopped = [k for k, _, f in rig.events("program") if f["state"] == "stopped"]
    assert stopped == [rig.by_n("move_end")[1]]
    assert stopped[0] * rig.period > q_time + 0.4
    assert rig.c.positions(1) == {"X": 10.0}


def test_r_while_the_program_waits_for_lines_leaves_it_waiting(rig):
    """An ``R`` to a rotary program that has run out of lines (still running, waiting for
    the host, PUM p213) changes nothing: no ``program`` event, the state stays ``waiting``,
    and the next line sent runs."""
    _start(rig, ["TM100 TA10 TS0 X1"])
    rig.run_until_idle()
    assert rig.c.coord(1)["program"]["state"] == "waiting"
    since = rig.c.log.last_seq
    rig.ok("R")
    rig.run_for(0.05)
    assert rig.events("program", since=since) == []
    assert rig.c.coord(1)["program"]["state"] == "waiting"
    rig.c.load_lines(1, ["X2"])
    rig.run_until_idle()
    assert rig.c.positions(1) == {"X": 2.0}


def test_q_calculates_no_further_line_the_calculated_moves_run_out(rig):
    """TUM p319 ``Q``: no further line is calculated after it, though move starts keep asking
    for calculation at their RTIs. Q during move 1 of five (moves 2 and 3 already calculated,
    two ahead, TUM p339): moves 1-3 run, the program stops at X3, lines 4 and 5 wait
    uncalculated."""
    _start(rig, ["TM100 TA10 TS0 X1", "X2", "X3", "X4", "X5"])
    rig.run_for(0.05)
    assert sorted(rig.by_n("line_calculated")) == [1, 2, 3]
    rig.ok("Q")
    rig.run_until_idle()
    assert sorted(rig.by_n("line_calculated")) == [1, 2, 3]
    assert sorted(rig.by_n("move_end")) == [1, 2, 3]
    assert rig.c.coord(1)["program"]["state"] == "stopped"
    assert rig.c.positions(1) == {"X": 3.0}


def test_word2_bit12_is_clear_during_a_linear_move(rig):
    """PSRM p195: bit 12 is the DWELL bit only; during a LINEAR move word 2 has no bit set
    (mode 000, moving)."""
    _start(rig, ["TM500 TA10 TS0 X5"])
    rig.run_for(0.2)
    assert _word2_bits(rig) == set()
