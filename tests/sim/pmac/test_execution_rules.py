"""The execution side of a running coordinate system, pinned to the manual (spec §1.1, §4.4,
§9.1-9.3, §11.3): ``A`` decelerates at Ixx15 (TUM p319; PSRM p73), CTRL-K freezes the
commanded positions (TUM p319), DWELL holds real time (TSRM p429), a synchronous write lands
at the first RTI at or after its move starts (TUM p250). Times are servo cycles.

The moves are ``TM1000 TA100 TS0``: from rest the ramp starts at the move's start, the
programmed start point is passed Ta/2 = 50 ms later, then 100 units/s for ``X100``.
"""

from __future__ import annotations

import math

import pytest

MOVE = "TM1000 TA100 TS0 X100"  # 100 units/s cruise from 100 ms after its start


def ceil_cycles(rig, ms: float) -> int:
    return math.ceil(rig.ms_cycles(ms) - 1e-6)


def _states(rig):
    return [(k, f["state"]) for k, _, f in rig.events("program")]


def _start(rig, lines, *setup):
    rig.rotary_setup()
    for s in setup:
        rig.ok(s)
    rig.c.load_lines(1, lines)
    rig.ok("R")


def _cruising(rig, *setup, after_s=0.5):
    """``MOVE`` then ``X200`` running; stop ``after_s`` after R (inside the cruise of line 1)."""
    _start(rig, [MOVE, "X200"], *setup)
    rig.run_for(after_s)
    k0 = rig.by_n("move_start")[1]
    return k0


# -- A: the abort deceleration at motor 1's Ixx15 -----------------------------------------


def test_a_decelerates_at_ixx15_and_the_move_ends_when_velocity_reaches_zero(rig):
    """PSRM p73: Ixx15 is the abort deceleration rate (cts/ms²). I115 = 0.001 → 1000
    units/s²: from 100 units/s the stop takes 100 ms and covers v²/2a = 5 units; the move
    ends (``move_end``) at the first servo cycle at or after that."""
    _cruising(rig, "I115=0.001")
    t_a = rig.c.now
    x_a = rig.c.positions(1)["X"]
    a = rig.cmd("A")
    k_a = rig.cyc(a.t_done)
    rig.run_until_idle()
    assert _states(rig)[-1] == (k_a, "aborted")
    assert rig.by_n("move_end") == {1: math.ceil((a.t_done + 0.1) / rig.period - 1e-9)}
    assert rig.c.positions(1)["X"] == pytest.approx(x_a + 100 * (a.t_done - t_a) + 5.0)
    assert sorted(rig.by_n("move_start")) == [1]


def test_during_the_abort_deceleration_velocity_falls_linearly(rig):
    """Constant deceleration: half-way through the 100 ms stop the axis has covered
    v·τ − a·τ²/2 = 5 − 1.25 = 3.75 units, and it holds the stop point afterwards."""
    _cruising(rig, "I115=0.001")
    a = rig.cmd("A")
    t = a.t_done
    x = rig.c.positions(1, t)["X"]
    assert rig.c.positions(1, t + 0.05)["X"] == pytest.approx(x + 3.75)
    assert rig.c.positions(1, t + 0.1)["X"] == pytest.approx(x + 5.0)
    rig.run_until_idle()
    assert rig.c.positions(1)["X"] == pytest.approx(x + 5.0)


def test_a_slower_ixx15_takes_proportionally_longer(rig):
    """I115 = 0.0005 → 500 units/s²: the stop from 100 units/s takes 200 ms, 10 units."""
    _cruising(rig, "I115=0.0005")
    a = rig.cmd("A")
    x = rig.c.positions(1, a.t_done)["X"]
    rig.run_until_idle()
    assert rig.by_n("move_end")[1] == math.ceil((a.t_done + 0.2) / rig.period - 1e-9)
    assert rig.c.positions(1)["X"] == pytest.approx(x + 10.0)


def test_the_abort_rate_is_motor_1s_ixx15_not_another_motors(rig):
    """``[INF]`` one Ixx15 for the CS: motor 1's (the X motor here). I215 does not change it."""
    _cruising(rig, "I115=0.001", "I215=0.0001")
    a = rig.cmd("A")
    rig.run_until_idle()
    assert rig.by_n("move_end")[1] == math.ceil((a.t_done + 0.1) / rig.period - 1e-9)


def test_a_during_a_dwell_ends_it_at_once_where_it_stands(rig):
    """A DWELL holds the commanded position (TSRM p429): nothing to decelerate, the dwell
    ends at the A's servo cycle and the axis stays at the dwell position."""
    _start(rig, ["TM100 TA10 TS0 X5", "DWELL1000", "X10"])
    rig.run_for(0.5)
    starts = rig.by_n("move_start")
    assert 2 in starts and 2 not in rig.by_n("move_end")  # dwelling
    a = rig.cmd("A")
    k_a = rig.cyc(a.t_done)
    rig.run_until_idle()
    assert rig.by_n("move_end")[2] == k_a
    assert _states(rig)[-1] == (k_a, "aborted")
    assert rig.c.positions(1) == {"X": 5.0}
    assert 3 not in rig.by_n("move_start")


def test_a_while_waiting_for_lines_aborts_without_a_move_end(rig):
    """PUM p213: a waiting program is stopped by A; no move executes, so none ends."""
    _start(rig, ["TM100 TA10 TS0 X5"])
    rig.run_until_idle()
    ends = rig.events("move_end")
    assert _states(rig)[-1][1] == "waiting"
    a = rig.cmd("A")
    assert _states(rig)[-1] == (rig.cyc(a.t_done), "aborted")
    rig.run_until_idle()
    assert rig.events("move_end") == ends
    assert rig.c.positions(1) == {"X": 5.0}
    rig.c.load_lines(1, ["X7"])
    rig.run_for(0.5)
    assert 2 not in rig.by_n("move_start")  # aborted: a new line waits for R


def test_a_with_the_time_base_at_zero_ends_the_move_where_it_was_frozen(rig):
    """``%0`` freezes the commanded positions (TSRM p260): at zero speed A has nothing to
    decelerate; the move ends at the A's servo cycle at the frozen position."""
    _cruising(rig, "I5194=8388607")
    rig.ok("%0")
    x = rig.c.positions(1)["X"]
    rig.run_for(1.0)
    a = rig.cmd("A")
    k_a = rig.cyc(a.t_done)
    rig.run_until_idle()
    assert rig.by_n("move_end")[1] == k_a
    assert rig.c.positions(1)["X"] == x


def test_r_after_a_starts_the_next_uncalculated_line_from_the_stop_point(rig):
    """TUM p319: after A, R continues with the lines not yet calculated (the calculated ones
    are discarded); the first one starts from rest at the stop point, at the RTI after R."""
    _cruising(rig, "I115=0.001")
    rig.c.load_lines(1, ["X300", "X400"])
    a = rig.cmd("A")
    x_a = rig.c.positions(1, a.t_done)["X"]
    rig.run_until_idle()
    calculated = set(rig.by_n("line_calculated"))
    first = min(n for n in (2, 3, 4) if n not in calculated)
    stop = rig.c.positions(1)["X"]
    r = rig.cmd("R")
    rig.run_until_idle()
    starts = rig.by_n("move_start")
    assert sorted(starts) == [1, *range(first, 5)]
    assert starts[first] == (rig.cyc(r.t_done) // 3 + 1) * 3  # calculated at the next RTI
    assert stop == pytest.approx(x_a + 5.0)  # v²/2a at I115 = 0.001
    assert rig.c.positions(1)["X"] == pytest.approx(400.0)


# -- CTRL-K: the commanded positions freeze --------------------------------------------------


def test_ctrl_k_freezes_the_commanded_position_and_ends_the_move_at_that_cycle(rig):
    """TUM p319 / TSRM p57: killed motors get no deceleration; the executing move ends now and
    nothing after it runs."""
    k0 = _cruising(rig)
    r = rig.cmd("\x0b")
    k = rig.cyc(r.t_done)
    x = 100 * (r.t_done - k0 * rig.period - 0.05)  # where the profile was at that instant
    rig.run_until_idle()
    assert rig.by_n("move_end") == {1: k}
    assert _states(rig)[-1] == (k, "aborted")
    assert rig.c.coord(1)["program"] == {"state": "aborted", "error": "killed"}
    assert rig.c.positions(1)["X"] == pytest.approx(x)
    assert rig.c.positions(1, rig.c.now + 1.0)["X"] == pytest.approx(x)
    assert sorted(rig.by_n("move_start")) == [1]


# -- DWELL: a stop, then real time -------------------------------------------------------------


def test_dwell_after_a_blended_move_starts_when_the_move_has_stopped_and_lasts_its_time(rig):
    """TSRM p429: a DWELL after a blended move first decelerates the move to a stop (its
    TA), then holds for the dwell time; the next move starts from rest after it."""
    _start(rig, ["TM100 TA20 TS0 X5", "DWELL50", "X10"])
    rig.run_until_idle()
    starts, ends = rig.by_n("move_start"), rig.by_n("move_end")
    assert ends[1] - starts[1] == ceil_cycles(rig, 120)  # TM + Ta: a stop
    assert starts[2] == ends[1]
    assert ends[2] == starts[2] + ceil_cycles(rig, 50)
    assert starts[3] >= ends[2]  # no blending across the dwell
    assert ends[3] - starts[3] == ceil_cycles(rig, 120)


# -- synchronous M-variables at the move's start --------------------------------------------


def test_a_synchronous_write_of_a_move_started_from_rest_fires_at_the_first_rti_of_the_move(
    make_rig,
):
    """TUM p250: the write goes with the start of the next move's execution; the queue is
    served at RTIs (I8 = 4: every 5th servo cycle). From rest the move starts at an RTI, so
    the write is on that very cycle."""
    rig = make_rig(i8=4)
    _start(rig, ["TM100 TA10 TS0 M1==3 X5"])
    rig.run_until_idle()
    ((k_m, _, f),) = rig.events("mvar")
    assert (f["name"], f["value"], f["sync"]) == ("M1", 3.0, True)
    assert k_m == rig.by_n("move_start")[1] and k_m % 5 == 0


# -- the stop at the end of a sequence -----------------------------------------------------


def test_the_final_deceleration_uses_the_ta_in_force_after_the_last_move_line(rig):
    """Spec §9.1 (PUM p175): "the final decel uses the TA/TS in force after the last move
    line". ``TA50`` after ``X5`` (TA10): 5 ms up to the start point, TM, 25 ms down."""
    _start(rig, ["TM100 TA10 TS0 X5", "TA50"])
    rig.run_until_idle()
    starts, ends = rig.by_n("move_start"), rig.by_n("move_end")
    assert ends[1] - starts[1] == ceil_cycles(rig, 5 + 100 + 25)


def test_a_move_run_at_half_speed_stops_in_twice_its_ta(make_rig):
    """TSRM p191: ``%`` is the time base: at 50 % TM and both ramps take twice as long."""
    rig = make_rig()
    rig.rotary_setup()
    rig.ok("I5194=8388607")
    rig.ok("%50")
    rig.c.load_lines(1, ["TM100 TA20 TS0 X5"])
    rig.ok("R")
    rig.run_until_idle()
    starts, ends = rig.by_n("move_start"), rig.by_n("move_end")
    assert ends[1] - starts[1] == ceil_cycles(rig, 2 * (100 + 20))
    assert rig.c.positions(1) == {"X": 5.0}


def test_q_lets_the_executing_move_end_in_a_stop_at_its_programmed_time(rig):
    """Spec §1.1: Q calculates nothing more; a lone calculated move ends in a stop
    (TM + Ta from rest) and the program is ``stopped`` at that cycle."""
    _start(rig, ["TM200 TA20 TS0 X5"])
    rig.run_for(0.05)
    rig.ok("Q")
    rig.c.load_lines(1, ["X10"])
    rig.run_until_idle()
    starts, ends = rig.by_n("move_start"), rig.by_n("move_end")
    assert sorted(starts) == [1]
    assert ends[1] - starts[1] == ceil_cycles(rig, 220)
    assert _states(rig)[-1] == (ends[1], "stopped")
    assert rig.c.positions(1) == {"X": 5.0}


def test_s_runs_one_move_to_a_stop_even_when_the_next_would_blend(rig):
    """TSRM p260 ``S``: single step — one move, ending in a stop, then ``stopped``; the next
    ``S`` runs the next move from rest."""
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM100 TA10 TS0 X5", "X10", "X15"])
    rig.ok("S")
    rig.run_until_idle()
    starts, ends = rig.by_n("move_start"), rig.by_n("move_end")
    assert sorted(starts) == [1] and ends[1] - starts[1] == ceil_cycles(rig, 110)
    assert _states(rig)[-1] == (ends[1], "stopped")
    assert rig.c.positions(1) == {"X": 5.0}
    s = rig.cmd("S")
    rig.run_until_idle()
    starts, ends = rig.by_n("move_start"), rig.by_n("move_end")
    assert sorted(starts) == [1, 2] and ends[2] - starts[2] == ceil_cycles(rig, 110)
    assert starts[2] > rig.cyc(s.t_done)
    assert rig.c.positions(1) == {"X": 10.0}


def test_a_dwell_ends_in_real_time_at_percent_zero_and_the_next_move_waits_for_the_time_base(
    rig,
):
    """TSRM p429: DWELL is real time, not scaled by ``%``; a move after it cannot run while
    the time base is 0 and starts when ``%`` returns."""
    _start(rig, ["TM100 TA10 TS0 X5", "DWELL500", "X10"], "I5194=8388607")
    rig.run_for(0.3)
    assert 2 in rig.by_n("move_start")  # dwelling
    rig.ok("%0")
    rig.run_for(2.0)
    ends = rig.by_n("move_end")
    assert ends[2] == rig.by_n("move_start")[2] + ceil_cycles(rig, 500)
    assert 3 not in rig.by_n("move_start")
    assert rig.c.positions(1) == {"X": 5.0}
    back = rig.cmd("%100")
    rig.run_until_idle()
    assert rig.by_n("move_start")[3] >= rig.cyc(back.t_done)
    assert rig.c.positions(1) == {"X": 10.0}


# -- blending ------------------------------------------------------------------------------


def test_the_next_moves_ta_is_clipped_to_twice_the_move_time_less_half_its_own_ta(rig):
    """Spec §9.1 (Quick Ref p49): TA(i+1) ≤ 2·(TM(i) − TA(i)/2), else clipped to that. Move 1
    (TM100, Ta 20 from rest) allows 180 ms; ``TA200`` is clipped, so the blend into move 2
    starts 90 ms before move 1's programmed end (at 10 + 100 ms): 20 ms after move 1 starts."""
    _start(rig, ["TM100 TA20 TS0 X5", "TA200 X10"])
    rig.run_until_idle()
    starts = rig.by_n("move_start")
    assert starts[2] - starts[1] == ceil_cycles(rig, 20)


def test_an_unclipped_next_ta_starts_the_blend_half_its_ta_before_the_boundary(rig):
    """The control case: TA100 ≤ 180 ms is kept; the blend starts 50 ms before move 1's
    programmed end, 60 ms after its start (spec §9.1: the blend is centred on the boundary)."""
    _start(rig, ["TM100 TA20 TS0 X5", "TA100 X10"])
    rig.run_until_idle()
    starts = rig.by_n("move_start")
    assert starts[2] - starts[1] == ceil_cycles(rig, 60)


def _line_at(rig, k: int, line: str) -> None:
    rig.c.env.run(until=k * rig.period)
    rig.c.load_lines(1, [line])


def test_segmentation_mode_a_line_planned_before_the_deceleration_point_is_blended(make_rig):
    """Seed 000 / spec §9.2: with Isx13 > 0 the last move's stop is decided where its
    deceleration starts, Ta/2 before its programmed end (here 500 ms after its start: 50 ms
    up to the start point, 500 ms, less 50). A line planned at an RTI before then blends."""
    rig = make_rig(i5113=10)
    _start(rig, ["TM500 TA100 TS0 X10"])
    rig.run_for(0.01)
    k0 = rig.by_n("move_start")[1]
    k_dec = k0 + ceil_cycles(rig, 500)
    _line_at(rig, k_dec - 7, "X20")  # two RTIs to be planned in
    rig.run_until_idle()
    starts, ends = rig.by_n("move_start"), rig.by_n("move_end")
    assert starts[2] == ends[1] == k_dec  # blended: the hand-off at the blend's start


def test_segmentation_mode_a_line_arriving_after_the_deceleration_point_starts_from_rest(
    make_rig,
):
    """Spec §9.2: a line arriving once the deceleration to a stop has begun is not blended:
    move 1 stops (TM + Ta after its start), move 2 starts from rest."""
    rig = make_rig(i5113=10)
    _start(rig, ["TM500 TA100 TS0 X10"])
    rig.run_for(0.01)
    k0 = rig.by_n("move_start")[1]
    k_dec = k0 + ceil_cycles(rig, 500)
    _line_at(rig, k_dec + 1, "X20")
    rig.run_until_idle()
    starts, ends = rig.by_n("move_start"), rig.by_n("move_end")
    assert ends[1] == k0 + ceil_cycles(rig, 600)
    assert starts[2] == ends[1]
    assert ends[2] - starts[2] == ceil_cycles(rig, 600)


def test_ctrl_k_during_the_i11_delay_cancels_the_start(make_rig):
    """PSRM I11: the moves are calculated, then wait I11 ms to start; CTRL-K in that time
    aborts the program (TUM p319) and the calculated move never starts."""
    rig = make_rig(i11=100)
    _start(rig, ["TM100 TA10 TS0 X5", "X10"])
    rig.run_for(0.05)
    assert rig.by_n("line_calculated") and not rig.events("move_start")
    rig.ok("\x0b")
    rig.run_until_idle()
    assert rig.events("move_start") == [] and rig.events("move_end") == []
    assert rig.c.coord(1)["program"] == {"state": "aborted", "error": "killed"}
    assert rig.c.positions(1) == {}


def test_ctrl_k_frees_the_words_of_calculated_lines_and_keeps_the_rest(rig):
    """TUM p319: the lookahead is lost with CTRL-K; lines not yet calculated stay in the
    rotary buffer."""
    _start(rig, ["TM1000 TA100 TS0 X100", "X200", "X300", "X400", "X500", "X600"])
    rig.run_for(0.3)
    calculated = set(rig.by_n("line_calculated"))
    rig.ok("\x0b")
    rig.run_until_idle()
    words = {f["n"]: f["words"] for _, _, f in rig.events("line_loaded")}
    assert 0 < len(calculated) < 6
    assert rig.c.rotary(1)["lines_ahead"] == 6 - len(calculated)
    assert rig.c.rotary(1)["used_words"] == sum(w for n, w in words.items() if n not in calculated)
    assert rig.events("move_start")[-1][2]["n"] == 1


def test_i8_changed_on_line_moves_the_planning_of_the_next_move_start_to_the_new_rti(rig):
    """Spec §4.1 (TUM p236): planning runs at RTIs, every I8+1 servo cycles, and a move start
    asks for planning at the next RTI. I8 changed while a program runs (after move 2 was
    planned): move 3's start asks for the next RTI of the new I8 (every 5th cycle)."""
    _start(rig, ["TM100 TA10 TS0 X1", "X2", "X3", "X4", "X5"])
    rig.run_for(0.01)
    k0 = rig.by_n("move_start")[1]
    rig.c.env.run(until=(k0 + ceil_cycles(rig, 150)) * rig.period)
    assert sorted(rig.by_n("line_calculated")) == [1, 2, 3, 4]
    rig.ok("I8=4")
    rig.run_until_idle()
    starts, calc = rig.by_n("move_start"), rig.by_n("line_calculated")
    k3 = starts[3]
    assert k3 == k0 + ceil_cycles(rig, 200)
    assert calc[5] == (k3 // 5 + 1) * 5 != (k3 // 3 + 1) * 3


def test_a_lines_words_are_freed_when_the_next_move_starts_executing(rig):
    """PUM p213 / spec §1.2: rotary space is freed as lines execute. When move 2 starts (the
    blend out of line 1 begins) line 1's words are free; line 2's stay until move 3 starts."""
    lines = ["TM100 TA10 TS0 X1", "X2", "X3", "X4", "X5"]
    _start(rig, lines)
    words = {f["n"]: f["words"] for _, _, f in rig.events("line_loaded")}
    total = sum(words.values())
    rig.run_for(0.01)
    k0 = rig.by_n("move_start")[1]
    seen = []
    for n, at_ms in ((1, 50), (2, 150), (3, 250), (4, 350)):
        rig.c.env.run(until=(k0 + ceil_cycles(rig, at_ms)) * rig.period)
        assert max(rig.by_n("move_start")) == n
        seen.append(rig.c.rotary(1)["used_words"])
    assert seen == [total - sum(words[i] for i in range(1, n)) for n in (1, 2, 3, 4)]
    assert words[1] > 2  # (line 1's words outnumber the line numbers here)


def test_s_given_while_running_stops_blending_the_calculated_moves_run_each_to_a_stop(rig):
    """TSRM p285: under ``S`` the continuous-motion request is 0: no blended sequence.
    ``[INF]`` ``S`` while a blended program runs: the hand-off into the next move was already
    decided (it starts blended); from then on each move ends in a stop, nothing more is
    calculated, and the moves already calculated run from rest, then ``stopped``."""
    _start(rig, ["TM100 TA10 TS0 X1", "X2", "X3", "X4", "X5", "X6"])
    rig.run_for(0.05)
    k0 = rig.by_n("move_start")[1]
    calculated = sorted(rig.by_n("line_calculated"))
    assert calculated == [1, 2, 3]
    rig.ok("S")
    assert not int(rig.ok("??")[:6], 16) & (1 << 4)  # continuous motion request off
    rig.run_until_idle()
    starts, ends = rig.by_n("move_start"), rig.by_n("move_end")
    assert sorted(starts) == calculated
    assert starts[2] == k0 + ceil_cycles(rig, 100)  # blended out of move 1
    assert ends[2] == k0 + ceil_cycles(rig, 210)  # then TM, and Ta/2 to a stop
    assert starts[3] == ends[2] and ends[3] - starts[3] == ceil_cycles(rig, 110)  # from rest
    assert _states(rig)[-1] == (ends[3], "stopped")
    assert rig.c.positions(1) == {"X": 3.0}


# -- PSET: the axis offset moves, the motor stays ------------------------------------------


def test_pset_of_an_axis_never_moved_keeps_a_scaled_motor_where_it_is(rig):
    """PSRM p179-180 (``#1->1000X``: 1000 counts per unit) and TSRM p31: ``PSET X5`` as the
    first line sets X to 5 with no motion; motor 1 stays at 0 counts, and the next ``X6``
    moves it one unit, 1000 counts. Y, set to its present value, changes nothing."""
    rig.ok("&1 #1->1000X #2->500Y")
    _start(rig, ["PSET X5", "TM100 TA10 TS0 X6"])
    rig.run_until_idle()
    ((_k, _t, f),) = rig.events("pset")
    assert f["positions"] == {"X": 5.0}
    assert rig.c.positions(1)["X"] == 6.0
    assert rig.c.motor_position(1) == 1000.0


def test_pset_of_two_axes_shifts_each_motor_by_its_own_scale(rig):
    """Two axes after a move: ``PSET X0 Y2`` (Y unchanged) leaves both motors where they were;
    the next move takes motor 1 (1000 cts/unit) and motor 2 (500 cts/unit) by their own
    distances from the new positions."""
    rig.ok("&1 #1->1000X #2->500Y")
    _start(rig, ["TM100 TA10 TS0 X1 Y2", "PSET X0 Y2", "X1 Y3"])
    rig.run_until_idle()
    assert rig.c.positions(1) == {"X": 1.0, "Y": 3.0}
    assert rig.c.motor_position(1) == 2000.0
    assert rig.c.motor_position(2) == 1500.0


def test_a_and_r_at_the_instant_a_move_starts_resume_at_the_next_rti_with_the_next_lines(rig):
    """TUM p319: A discards the calculated moves; R continues with the lines not yet
    calculated, planned at the next RTI (TUM p236). A and R in the very servo cycle the first
    move starts (nothing moving yet: the stop is immediate): lines 4 and on run from the RTI
    after it, once each, and the program ends ``waiting`` for more."""
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM20 TA10 TS0 X1", "X2", "X3", "X4", "X5", "X6"])
    rig.c.run(1)
    env = rig.c.env
    while not rig.events("move_start"):
        env.step()
    k0 = rig.events("move_start")[0][0]
    while env.peek() <= env.now:  # the rest of that cycle's work
        env.step()
    assert sorted(rig.by_n("line_calculated")) == [1, 2, 3]
    rig.c.abort(1)
    rig.c.run(1)
    rig.run_until_idle()
    starts = [(k, f["n"]) for k, _, f in rig.events("move_start")]
    assert starts[0] == (k0, 1)
    assert [n for _, n in starts[1:]] == [4, 5, 6]
    assert starts[1][0] == (k0 // 3 + 1) * 3
    assert [s for _, s in _states(rig)] == ["running", "aborted", "running", "waiting"]
    assert rig.c.positions(1) == {"X": 6.0}


def test_segmentation_mode_with_isx13_1_ms_blends_a_line_entered_during_the_last_move(make_rig):
    """TSRM p177: any Isx13 > 0 puts the CS in segmentation mode (1 ms is the smallest), and
    with it rotary blend-on-the-fly (seed 000): a line entered while the last move runs,
    before its deceleration, is blended in without stopping."""
    rig = make_rig(i5113=1)
    _start(rig, ["TM500 TA100 TS0 X10"])
    rig.run_for(0.3)
    rig.c.load_lines(1, ["X20"])
    rig.run_until_idle()
    starts, ends = rig.by_n("move_start"), rig.by_n("move_end")
    assert starts[2] == ends[1] == starts[1] + ceil_cycles(rig, 500)
    assert [s for _, s in _states(rig)] == ["running", "waiting"]


def test_each_blend_is_centred_on_its_boundary_with_the_ta_of_the_move_it_enters(rig):
    """Spec §9.1: the blend into move i+1 takes move i+1's TA, centred on the programmed
    boundary. TA 20, then 60, then 10 (all within 2·(TM − TA/2)): move 2 starts 30 ms before
    move 1's programmed end (10 + 100 ms), move 3 5 ms before move 2's (210 ms)."""
    _start(rig, ["TM100 TA20 TS0 X1", "TA60 X2", "TA10 X3"])
    rig.run_until_idle()
    starts = rig.by_n("move_start")
    assert starts[2] - starts[1] == ceil_cycles(rig, 80)
    assert starts[3] - starts[1] == ceil_cycles(rig, 205)


def test_a_blend_start_falling_exactly_on_a_servo_cycle_starts_the_move_on_that_cycle(make_rig):
    """Servo-cycle quantisation (spec §9.1, TUM p236): the next move starts at the first servo
    cycle at or after its blend start. With a 1 kHz servo clock the blend into move 2 starts
    exactly 100 ms (100 cycles) after move 1: on that cycle, not the one after."""
    rig = make_rig(servo_hz=1000.0)
    _start(rig, ["TM100 TA20 TS0 X5", "X10"])
    rig.run_until_idle()
    starts = rig.by_n("move_start")
    assert starts[2] - starts[1] == 100
