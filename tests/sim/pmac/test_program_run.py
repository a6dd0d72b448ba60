"""Running a rotary program: R, run-out, resume, Q, A, blend-on-the-fly (seed 000, PUM p213,
TUM p319, spec §1.1, §1.2, §9.2)."""

from __future__ import annotations

import math


def next_rti(k: int, m: int = 3) -> int:
    return (k // m + 1) * m


def _states(rig):
    return [(k, f["state"]) for k, _, f in rig.events("program")]


def _enter_x20_during_a_500ms_move(rig, after_r_s: float):
    """Run ``TM500 TA100 TS0 X10`` from a fresh rotary buffer, enter ``X20`` ``after_r_s`` after
    R, run to the end; the move_start and move_end cycles by line number."""
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM500 TA100 TS0 X10"])
    rig.ok("R")
    rig.run_for(after_r_s)
    rig.c.load_lines(1, ["X20"])
    rig.run_until_idle()
    return rig.by_n("move_start"), rig.by_n("move_end")


def test_r_on_an_empty_rotary_buffer_waits_and_runs_the_first_line_when_it_arrives(rig):
    """Seed 000: "If the R command is given for an empty rotary buffer, the buffer will simply
    wait for a command to be given to it, and then execute that command immediately."""
    rig.rotary_setup()
    r = rig.cmd("R")
    rig.run_for(0.05)
    k_r = rig.cyc(r.t_done)
    assert _states(rig) == [(k_r, "running"), (next_rti(k_r), "waiting")]
    rig.ok("OPEN ROT")
    load = rig.cmd("TM100 TA10 TS0 X1")
    k_load = rig.cyc(load.t_done)
    rig.run_until_idle()
    assert rig.by_n("move_start")[1] == next_rti(k_load)
    assert _states(rig)[2] == (next_rti(k_load), "running")


def test_running_out_of_lines_is_waiting_not_an_error_and_more_lines_resume_without_r(rig):
    """Seed 000 / PUM p213: when calculation catches up with the load point the program
    suspends, still running; new lines continue it without a new R."""
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM100 TA10 TS0 X1"])
    rig.ok("R")
    rig.run_for(1.0)
    end1 = rig.by_n("move_end")[1]
    assert _states(rig)[-1] == (end1, "waiting")
    assert rig.c.coord(1)["program"] == {"state": "waiting"}
    assert int(rig.ok("??")[:6], 16) & 1  # word 1 bit 0: still running a program
    k_load = rig.cyc(rig.c.now)
    rig.c.load_lines(1, ["X2"])
    rig.run_until_idle()
    assert rig.by_n("move_start")[2] == next_rti(k_load)
    assert [s for _, s in _states(rig)] == ["running", "waiting", "running", "waiting"]


def test_q_stops_after_the_moves_already_calculated(rig):
    """Spec §1.1: Q lets the calculated moves finish, calculates nothing more, then stops."""
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM100 TA10 TS0 X1", "X2", "X3", "X4", "X5", "X6"])
    rig.ok("R")
    rig.run_for(0.15)
    q = rig.cmd("Q")
    k_q = rig.cyc(q.t_done)
    rig.run_until_idle()
    calc = rig.by_n("line_calculated")
    assert all(k <= k_q for k in calc.values())
    started = sorted(rig.by_n("move_start"))
    assert started == sorted(calc)  # every calculated move ran, nothing else
    last_end = max(rig.by_n("move_end").values())
    assert _states(rig)[-1] == (last_end, "stopped")
    assert rig.ok("PR") == str(6 - len(calc))


def test_q_stops_a_program_waiting_for_lines(rig):
    """PUM p213: a Q or A is needed to truly stop a program that ran out of lines."""
    rig.rotary_setup()
    rig.ok("R")
    rig.run_for(0.01)
    q = rig.cmd("Q")
    assert _states(rig)[-1] == (rig.cyc(q.t_done), "stopped")
    rig.c.load_lines(1, ["X1"])
    rig.run_for(0.5)
    assert rig.events("move_start") == []


def test_a_aborts_now_decelerates_and_discards_queued_synchronous_writes(rig):
    """TUM p319: A breaks into the trajectory, decelerates at Ixx15, discards lookahead and
    queued synchronous M-variable assignments."""
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM1000 TA100 TS0 X100", "M1==1", "X200", "X300"])
    rig.ok("R")
    rig.run_for(0.3)
    a = rig.cmd("A")
    k_a = rig.cyc(a.t_done)
    rig.run_until_idle()
    assert _states(rig)[-1] == (k_a, "aborted")
    # 100 units/s at 0.25 counts/ms² stops in 0.4 ms: the next servo cycle.
    assert rig.by_n("move_end")[1] == k_a + math.ceil(0.4e-3 / rig.period)
    assert rig.events("mvar") == []
    assert sorted(rig.by_n("move_start")) == [1]
    x = rig.c.positions(1)["X"]
    assert 0 < x < 100
    assert rig.c.rotary(1)["used_words"] == 0  # calculated-but-unexecuted lines discarded


def test_r_after_abort_continues_with_the_uncalculated_lines(rig):
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM100 TA10 TS0 X1", "X2", "X3", "X4", "X5"])
    rig.ok("R")
    rig.run_for(0.05)
    rig.ok("A")
    rig.run_for(0.05)
    rig.ok("R")
    rig.run_until_idle()
    assert sorted(rig.by_n("move_start")) == [1, 4, 5]
    assert rig.c.positions(1)["X"] == 5.0


def test_segmentation_mode_blends_a_line_that_arrives_before_deceleration(make_rig):
    """Seed 000 / PUM p213: with Isx13 > 0, a line entered while the last line executes,
    before deceleration to a stop starts, is blended in without stopping."""
    rig = make_rig(i5113=10)
    starts, ends = _enter_x20_during_a_500ms_move(rig, 0.3)
    assert starts[2] == ends[1] == starts[1] + math.ceil(0.5 / rig.period - 1e-6)
    assert [s for _, s in _states(rig)] == ["running", "waiting"]


def test_segmentation_mode_line_after_deceleration_started_starts_from_rest(make_rig):
    rig = make_rig(i5113=10)
    starts, ends = _enter_x20_during_a_500ms_move(rig, 0.52)
    assert ends[1] == starts[1] + math.ceil(0.6 / rig.period - 1e-6)  # stopped
    assert starts[2] == ends[1]


def test_without_segmentation_a_move_started_with_nothing_after_it_stops(rig):
    """[INF] Isx13 = 0: no blend-on-the-fly; a line arriving during the last move runs after
    a stop."""
    starts, ends = _enter_x20_during_a_500ms_move(rig, 0.3)
    assert ends[1] == starts[1] + math.ceil(0.6 / rig.period - 1e-6)
    assert starts[2] == ends[1]


def test_s_runs_one_move_then_stops(rig):
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM100 TA10 TS0 X1", "X2"])
    rig.ok("S")
    rig.run_until_idle()
    assert sorted(rig.by_n("move_start")) == [1]
    assert _states(rig)[-1][1] == "stopped"


def test_close_does_not_stop_execution(rig):
    """PUM p213: CLOSE only stops entry."""
    rig.rotary_setup()
    rig.ok("OPEN ROT")
    rig.ok("TM100 TA10 TS0 X1")
    rig.ok("X2")
    rig.ok("R")
    rig.ok("CLOSE")
    rig.run_until_idle()
    assert sorted(rig.by_n("move_end")) == [1, 2]


def test_executed_lines_free_their_words(rig):
    """Seed 000: executed lines are overwritten — the rotary buffer is a ring."""
    rig.rotary_setup(words=10)
    rig.c.load_lines(1, ["TM100 TA10 TS0 X1 Y1", "X2 Y2", "X3 Y3"])
    assert rig.c.rotary(1)["used_words"] == 5 + 2 + 2
    rig.ok("R")
    rig.run_until_idle()
    assert rig.c.rotary(1)["used_words"] == 0
    assert rig.c.rotary(1)["free_words"] == 10


def test_r_and_q_during_the_abort_deceleration_end_stopped(rig):
    """Found by the state machine: R then Q while A's deceleration runs must still stop."""
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM1000 X10"] * 5)
    rig.c.run(1)
    rig.run_for(0.5)
    rig.c.abort(1)
    rig.c.run(1)
    rig.c.quit(1)
    rig.run_until_idle()
    assert rig.c.log.events("program")[-1]["state"] == "stopped"


def _m1_queued_behind_the_last_move(rig) -> None:
    """``X1`` then ``M1==1`` and nothing more: the program runs out of lines with the
    synchronous write queued for the start of the next move."""
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM100 TA10 TS0 X1", "M1==1"])
    rig.ok("R")
    rig.run_for(0.3)
    assert rig.c.coord(1)["program"] == {"state": "waiting"}
    assert rig.events("mvar") == []


def test_a_queued_synchronous_write_fires_at_the_start_of_the_next_move(rig):
    """The control case for the two below: with no Q or A the queued write belongs to the next
    move and fires at its start (TUM p250)."""
    _m1_queued_behind_the_last_move(rig)
    rig.c.load_lines(1, ["X2"])
    rig.run_until_idle()
    (start,) = [k for k, _, f in rig.events("move_start") if f["n"] == 3]
    assert [(k, f["name"]) for k, _, f in rig.events("mvar")] == [(start, "M1")]


def test_q_leaves_queued_synchronous_writes_in_the_queue_they_fire_at_the_next_r(rig):
    """TUM p250: synchronous assignments "left in the queue because the program ended or was
    stopped" stay there (MFLUSH removes them): after Q and a new R the write fires at the
    first RTI at or after the start of the next move. (A discards them, below.)"""
    _m1_queued_behind_the_last_move(rig)
    rig.ok("Q")
    assert rig.c.coord(1)["program"] == {"state": "stopped"}
    rig.c.load_lines(1, ["X2"])
    rig.ok("R")
    rig.run_until_idle()
    assert [f["n"] for _, _, f in rig.events("move_start")] == [1, 3]
    (start,) = [k for k, _, f in rig.events("move_start") if f["n"] == 3]
    assert [(k, f["name"]) for k, _, f in rig.events("mvar")] == [(-(-start // 3) * 3, "M1")]


def test_mflush_after_q_removes_the_queued_write_it_never_fires(rig):
    """TUM p250: "they can be removed from the queue with the on-line MFLUSH command"."""
    _m1_queued_behind_the_last_move(rig)
    rig.ok("Q")
    assert rig.ok("MFLUSH") == ""
    rig.c.load_lines(1, ["X2"])
    rig.ok("R")
    rig.run_until_idle()
    assert [f["n"] for _, _, f in rig.events("move_start")] == [1, 3]
    assert rig.events("mvar") == []


def test_a_discards_queued_synchronous_writes_they_do_not_fire_after_the_next_r(rig):
    """TUM p319: A discards the queued synchronous M-variable assignments with the lookahead."""
    _m1_queued_behind_the_last_move(rig)
    rig.ok("A")
    rig.c.load_lines(1, ["X2"])
    rig.ok("R")
    rig.run_until_idle()
    assert [f["n"] for _, _, f in rig.events("move_start")] == [1, 3]
    assert rig.events("mvar") == []
