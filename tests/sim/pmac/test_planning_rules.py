"""When a coordinate system calculates ("plans") program lines, pinned to the manual: only at
RTIs, the first RTI strictly after the move start that sets the "plan the next move" flag
(TUM p236); two moves ahead of the executing one for LINEAR with Isx13 = 0, one otherwise
(TUM p339; spec §4.2, §9.3), three from rest; with the special lookahead Isx20 segments of
Isx13 ms ahead (TSRM p181); nothing after a DWELL until it ends, nothing while the program is
not running; a line arriving while running is calculated at the next RTI when calculation
wants it; I11 from rest (PSRM I11); values, modes and settings read at calculation. Times are
servo cycles; I8 = 0 makes every servo cycle an RTI.

Several tests run a *twin*: the same program on a second controller (the simulation is
deterministic), with one more line arriving one servo cycle before an instant the first run
showed — the move start, dwell end or R after which calculation must wait for the next RTI.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import pytest

from tests.sim.pmac.conftest import Rig


def _states_at(rig: Rig) -> dict[str, int]:
    """The cycle of each program state's latest ``program`` event."""
    return {f["state"]: k for k, _, f in rig.events("program")}


def _settle(rig: Rig) -> None:
    """Run 3 s of simulated time: every program here has ended well before."""
    rig.run_until_idle(limit_s=3.0)


def _run_to(rig: Rig, k: int) -> None:
    """Run the simulation up to servo cycle ``k`` (events due at ``k`` not yet processed)."""
    rig.c.env.run(until=k * rig.period)


def _next_rti(k: int, m: int = 3) -> int:
    """The first RTI strictly after cycle ``k`` (cycles divisible by I8+1 = ``m``)."""
    return (k // m + 1) * m


def _start(rig: Rig, lines: list[str], *setup: str) -> None:
    """The ``setup`` commands, a rotary buffer for CS 1 with ``lines`` in it, then ``R``."""
    for s in setup:
        rig.ok(s)
    rig.rotary_setup()
    rig.c.load_lines(1, lines)
    rig.ok("R")


def _twin(
    make_rig: Callable[[], Rig], begin: Callable[[Rig], None], instant: Callable[[Rig], int]
) -> tuple[Rig, int]:
    """Run ``begin`` on a reference controller to the end and read ``instant`` of it; run it
    again on a twin up to one servo cycle before that instant. Returns (twin, instant)."""
    ref = make_rig()
    begin(ref)
    _settle(ref)
    k = instant(ref)
    twin = make_rig()
    begin(twin)
    _run_to(twin, k - 1)
    return twin, k


# -- depth: how many moves are kept calculated -------------------------------------------


def test_with_isx13_0_a_line_arriving_with_one_move_calculated_ahead_is_calculated_at_the_next_rti(
    rig,
):
    """TUM p339: with Isx13 = 0 LINEAR calculates two moves ahead of the executing one. X1
    executes, X2 is calculated, nothing else: X3 arriving at cycle 100 is wanted and is
    calculated at the next RTI, so X2 blends into it (X2 ends where X3 starts)."""
    _start(rig, ["TM100 TA10 TS0 X1", "X2"])
    _run_to(rig, 100)
    rig.c.load_lines(1, ["X3"])
    _settle(rig)
    assert rig.by_n("line_calculated")[3] == _next_rti(100)
    assert rig.by_n("move_start")[3] == rig.by_n("move_end")[2]


def test_during_the_i11_delay_linear_calculates_three_moves_from_rest(rig):
    """TUM p339 / PSRM I11: from rest no move executes yet, so two ahead of the first is three
    moves. With I11 = 50 ms the first move waits; X1 and X2 are calculated, X3 arriving in
    the delay is wanted and calculated at the next RTI, before the first move starts."""
    _start(rig, ["TM100 TA10 TS0 X1", "X2"], "I11=50")
    k_r = rig.cyc(rig.c.now)
    _run_to(rig, k_r + 30)
    rig.c.load_lines(1, ["X3"])
    _settle(rig)
    k_go = rig.by_n("move_start")[1]
    assert rig.by_n("line_calculated")[3] == _next_rti(k_r + 30) < k_go


def test_segmented_linear_calculates_one_move_ahead_the_next_at_the_rti_after_a_move_starts(
    make_rig,
):
    """TSRM p177 / TUM p339: with Isx13 > 0 (no lookahead buffer) LINEAR keeps one move
    calculated beyond the executing one. X1 executes with X2 calculated: X3 arriving one cycle
    before X2 starts is not wanted yet; X2's start asks for it, calculated at the first RTI
    strictly after that start (TUM p236), not at the start's own cycle."""

    def begin(rig: Rig) -> None:
        _start(rig, ["LINEAR ABS TM200 TA100 TS0 X1", "TA10 X2"], "I8=0", "I5113=10")

    rig, k_s = _twin(make_rig, begin, lambda ref: ref.by_n("move_start")[2])
    rig.c.load_lines(1, ["X3"])
    _settle(rig)
    assert rig.by_n("move_start")[2] == k_s
    assert rig.by_n("line_calculated")[3] == k_s + 1


def _lookahead(isx20: int, *more: str) -> tuple[str, ...]:
    """The special lookahead active: Isx13 = 10 ms segments, Isx20 of them, a buffer."""
    return ("I5113=10", f"I5120={isx20}", "&1 DEFINE LOOKAHEAD 50,10", *more)


def test_tsrm_p181_a_line_arriving_short_of_the_horizon_is_calculated_at_the_next_rti(rig):
    """TSRM p181: the special lookahead calculates Isx20 segments (here 30 × 10 ms = 300 ms)
    ahead. X1 executes, X2 (100 ms) is all that is calculated: short of the horizon, so X3
    arriving at cycle 100 is calculated at the next RTI."""
    _start(rig, ["LINEAR ABS TM100 TA10 TS0 X1", "X2"], *_lookahead(30))
    _run_to(rig, 100)
    assert 2 in rig.by_n("line_calculated") and 2 not in rig.by_n("move_start")
    rig.c.load_lines(1, ["X3"])
    _settle(rig)
    assert rig.by_n("line_calculated")[3] == _next_rti(100)


def test_tsrm_p181_with_the_horizon_covered_a_line_waits_for_the_rti_after_the_next_move_start(
    make_rig,
):
    """Horizon 300 ms: while X1 executes, X2 and X3 (200 ms each) cover it. X4 arriving one
    cycle before X2 starts is not wanted; X2's start leaves X3 alone, short of the horizon,
    and X4 is calculated at the first RTI strictly after that start (TUM p236)."""

    def begin(rig: Rig) -> None:
        lines = ["LINEAR ABS TM200 TA100 TS0 X1", "TA10 X2", "X3"]
        _start(rig, lines, *_lookahead(30, "I8=0"))

    rig, k_s = _twin(make_rig, begin, lambda ref: ref.by_n("move_start")[2])
    assert {2, 3} <= set(rig.by_n("line_calculated"))
    rig.c.load_lines(1, ["X4"])
    _settle(rig)
    assert rig.by_n("move_start")[2] == k_s
    assert rig.by_n("line_calculated")[4] == k_s + 1


def test_tsrm_p181_from_rest_in_the_i11_delay_a_covered_horizon_waits_for_the_first_move_start(
    make_rig,
):
    """From rest with I11 = 50 ms the special lookahead (150 ms) calculates X1 and X2 (100 ms
    each; two from rest). X3 arriving one cycle before the delayed first move starts is not
    wanted; that start leaves X2 alone, short of the horizon, and X3 is calculated at the first
    RTI strictly after it."""

    def begin(rig: Rig) -> None:
        _start(rig, ["LINEAR ABS TM100 TA10 TS0 X1", "X2"], *_lookahead(15, "I8=0", "I11=50"))

    rig, k_go = _twin(make_rig, begin, lambda ref: ref.by_n("move_start")[1])
    rig.c.load_lines(1, ["X3"])
    _settle(rig)
    assert rig.by_n("move_start")[1] == k_go
    assert rig.by_n("line_calculated")[3] == k_go + 1


def test_tsrm_p181_the_horizon_is_counted_in_program_time_at_a_feedrate_override(rig):
    """At %50 moves take twice as long in real time, but the horizon is Isx20 segments of
    Isx13 ms of the program (20 × 10 = 200 ms): four TM49.96 moves are still short of it and a
    fifth is calculated at the first RTI (the mode line and five moves), as at %100."""
    _start(rig, ["LINEAR ABS TA10 TS0 TM49.96"] + [f"X{i}" for i in range(1, 12)],
           *_lookahead(20, "%50"))  # fmt: skip
    rig.run_for(0.01)
    ks = [k for k, _, _ in rig.events("line_calculated")]
    assert sum(1 for k in ks if k == ks[0]) == 6


def test_s_with_the_special_lookahead_calculates_only_the_move_it_runs(rig):
    """TSRM (S): a single step runs one move, then the program stops; the special lookahead's
    horizon (300 ms, four 100 ms moves loaded) does not make it calculate further."""
    rig.ok("I5113=10")
    rig.ok("I5120=30")
    rig.ok("&1 DEFINE LOOKAHEAD 50,10")
    rig.rotary_setup()
    rig.c.load_lines(1, ["LINEAR ABS TM100 TA10 TS0 X1", "X2", "X3", "X4"])
    rig.ok("S")
    _settle(rig)
    assert sorted(rig.by_n("line_calculated")) == [1]
    assert sorted(rig.by_n("move_start")) == [1]
    assert rig.c.coord(1)["program"] == {"state": "stopped"}


def test_raising_isx20_while_running_lengthens_the_horizon_for_the_next_line_arriving(rig):
    """I-variables are re-read when they change: horizon 150 ms, X2 and X3 (100 ms each)
    calculated while X1 executes; I5120 = 40 makes it 400 ms, so X4 arriving right after is
    wanted and calculated at the next RTI."""
    _start(rig, ["LINEAR ABS TM100 TA10 TS0 X1", "X2", "X3"], *_lookahead(15))
    _run_to(rig, 100)
    assert {2, 3} <= set(rig.by_n("line_calculated"))
    rig.ok("I5120=40")
    k = rig.cyc(rig.c.now)
    rig.c.load_lines(1, ["X4"])
    _settle(rig)
    assert rig.by_n("line_calculated")[4] == _next_rti(k)


# -- breaks and a program not running -------------------------------------------------------


def test_a_line_arriving_during_a_dwell_is_calculated_at_the_rti_after_the_dwell_ends(make_rig):
    """A DWELL stops lookahead: nothing after it is calculated until it has finished, then
    at the next RTI. A line arriving one cycle before the dwell ends is calculated at the first
    RTI strictly after the end (I8 = 0: the next cycle), not at the end's own cycle."""

    def begin(rig: Rig) -> None:
        _start(rig, ["DWELL100"], "I8=0")

    rig, k_e = _twin(make_rig, begin, lambda ref: ref.by_n("move_end")[1])
    rig.c.load_lines(1, ["TM100 TA10 TS0 X1"])
    _settle(rig)
    assert rig.by_n("move_end")[1] == k_e
    assert rig.by_n("line_calculated")[2] == rig.by_n("move_start")[2] == k_e + 1


def _idle(rig: Rig) -> None:
    rig.rotary_setup()


def _stopped(rig: Rig) -> None:
    _start(rig, ["TM100 TA10 TS0 X1"])
    _settle(rig)
    rig.ok("Q")


def _aborted(rig: Rig) -> None:
    _start(rig, ["TM100 TA10 TS0 X1"])
    _settle(rig)
    rig.ok("A")


@pytest.mark.parametrize("state,before", [("idle", _idle), ("stopped", _stopped),
                                          ("aborted", _aborted)])  # fmt: skip
def test_a_line_arriving_while_the_program_is_not_running_is_calculated_only_after_r(
    rig, state, before
):
    """PUM p213 / TUM p236: a program that is not running calculates nothing; ``R`` asks for
    calculation at the first RTI strictly after it. Here the line arrives with the ``R`` on
    its way (answered one servo cycle later, I8 = 0: at the next RTI) and is calculated at
    the RTI after the ``R``, not at the ``R``'s own cycle."""
    rig.ok("I8=0")
    before(rig)
    assert rig.c.coord(1)["program"]["state"] == state
    r = rig.c.terminal("R")
    rig.c.load_lines(1, ["TM100 TA10 TS0 X5"])
    _settle(rig)
    k_r = rig.cyc(r.t_done)
    calc = [k for k, _, f in rig.events("line_calculated") if k >= k_r]
    assert calc == [k_r + 1]


def test_q_calculates_nothing_more_even_with_a_planning_request_from_before_it(rig):
    """Spec §1.1 / TSRM (Q): the calculated moves finish, nothing more is calculated, then
    the program is stopped. With I8 = 255 (an RTI every 256 cycles) X1's start asks for
    planning at the next RTI (cycle 512); Q comes first and X1-X3 have stopped by then: at
    that RTI X4 and X5 stay uncalculated and nothing moves."""
    _start(rig, ["TM20 TA10 TS0 X1", "X2", "X3", "X4", "X5"], "I8=255")
    _run_to(rig, 260)
    assert sorted(rig.by_n("line_calculated")) == [1, 2, 3]
    rig.ok("Q")
    _settle(rig)
    assert max(rig.by_n("move_end").values()) < 512
    assert sorted(rig.by_n("line_calculated")) == [1, 2, 3]
    assert sorted(rig.by_n("move_start")) == [1, 2, 3]
    assert rig.c.coord(1)["program"] == {"state": "stopped"}


def test_isx13_written_after_r_applies_to_the_first_rtis_calculation(rig):
    """I-variables are read when calculation runs: ``R I5113=10`` (one command line) sets
    segmentation mode after R asked for the first RTI's calculation, so that RTI calculates
    segmented LINEAR's two moves from rest, not the three of Isx13 = 0."""
    rig.rotary_setup()
    rig.c.load_lines(1, ["LINEAR ABS TM100 TA10 TS0 X1", "X2", "X3", "X4"])
    k_r = rig.cyc(rig.cmd("R I5113=10").t_done)
    rig.run_for(0.02)
    assert rig.by_n("line_calculated") == {1: _next_rti(k_r), 2: _next_rti(k_r)}


def test_i11_times_a_start_from_rest_not_a_line_arriving_during_motion(rig):
    """PSRM I11: the delay from the run signal (or a line starting a sequence from rest) to
    the first move; a line arriving while a move executes starts no such deadline. I8 = 255
    (RTIs 256 cycles apart), I11 = 170 ms (384 cycles): X2 arrives during X1 (cycle 600) and
    runs after it; X3 arrives while waiting (cycle 950) with calculation already due at the RTI
    of cycle 1024. At cycle 984, 384 cycles after X2 arrived, nothing is due: X3 is calculated
    at that RTI and runs, no run-time error."""
    _start(rig, ["TM200 TA10 TS0 X1"], "I8=255", "I11=170")
    _run_to(rig, 600)
    rig.c.load_lines(1, ["TM20 X2"])
    _run_to(rig, 950)
    assert rig.c.coord(1)["program"] == {"state": "waiting"}
    assert sorted(rig.by_n("move_end")) == [1, 2]
    rig.c.load_lines(1, ["X3"])
    _settle(rig)
    assert "error" not in rig.c.coord(1)["program"]
    assert [s for _, _, s in rig.events("program")][-3:] == [
        {"cs": 1, "state": "waiting"}, {"cs": 1, "state": "running"},
        {"cs": 1, "state": "waiting"},
    ]  # fmt: skip
    assert rig.by_n("line_calculated")[3] == 1024 < rig.by_n("move_start")[3]


# -- starting from rest ------------------------------------------------------------------------


def test_at_1_percent_override_the_first_move_starts_at_the_first_rti(rig):
    """TSRM (%): only ``%0`` holds motion; at %1 (reached at once: Isx94 at its maximum) the
    first move is calculated and starts at the first RTI after R, as at %100."""
    _start(rig, ["TM10 TA10 TS0 X1"], "I5194=8388607", "%1")
    k_r = _states_at(rig)["running"]
    rig.run_for(0.05)
    assert rig.ok("%") == "1"
    assert rig.by_n("move_start")[1] == rig.by_n("line_calculated")[1] == _next_rti(k_r)


def test_with_i11_0_the_first_move_starts_within_the_rti_that_calculates_it(rig):
    """PSRM I11 = 0: the first move starts as soon as calculated, in the same RTI. An ``A``
    answered at that very cycle finds the move started: it aborts it there (``move_start``,
    ``aborted`` and ``move_end`` all at the first RTI)."""
    _start(rig, ["TM100 TA10 TS0 X1"])
    k = _next_rti(_states_at(rig)["running"])
    _run_to(rig, k - 1)
    a = rig.c.terminal("A")  # answered one servo cycle later: at the RTI
    _settle(rig)
    assert rig.cyc(a.t_done) == k
    assert rig.by_n("line_calculated") == rig.by_n("move_start") == {1: k}
    assert _states_at(rig)["aborted"] == rig.by_n("move_end")[1] == k


def test_an_i11_written_after_r_delays_the_first_move_from_the_rti_that_calculates_it(rig):
    """PSRM I11, read when the first move is calculated: ``R I11=50`` (one command line) asks
    for calculation with I11 = 0, then sets 50 ms; the first RTI calculates X1 and it starts
    50 ms later, on the first servo cycle at or after then."""
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM100 TA10 TS0 X1"])
    k = _next_rti(rig.cyc(rig.cmd("R I11=50").t_done))
    _settle(rig)
    assert rig.by_n("line_calculated")[1] == k
    assert rig.by_n("move_start")[1] == k + math.ceil(rig.ms_cycles(50) - 1e-9)


def test_feed_hold_during_the_i11_delay_keeps_the_first_move_from_starting(rig):
    """TSRM (%): ``%0`` holds motion. Given during the I11 delay (50 ms) before the first
    move, the move does not start when the delay is up; ``%100`` starts it at once."""
    _start(rig, ["TM100 TA10 TS0 X1"], "I5194=8388607", "I11=50")
    rig.ok("%0")
    rig.run_for(0.2)
    assert 1 in rig.by_n("line_calculated") and rig.by_n("move_start") == {}
    k = rig.cyc(rig.cmd("%100").t_done)
    _settle(rig)
    assert rig.by_n("move_start") == {1: k}


# -- program order ------------------------------------------------------------------------------


def test_a_constant_line_after_a_spline_series_and_a_circle_mode_word_runs_after_the_series(rig):
    """TUM p290: a SPLINE series ends at another mode's move, its last point with the added
    segment to rest first. ``CIRCLE1`` alone (TM kept from the series) then ``X5`` (no
    centre: a straight move): the moves run in program order and X ends at 5."""
    _start(rig, ["SPLINE1 TM100 ABS X1", "X2", "CIRCLE1", "X5"])
    _settle(rig)
    starts = rig.by_n("move_start")
    assert sorted(starts, key=starts.__getitem__) == [1, 2, 4]
    assert rig.c.positions(1) == {"X": 5.0}


# -- values computed at calculation --------------------------------------------------------------


def test_pset_takes_an_expression_evaluated_when_it_is_calculated(rig):
    """TSRM p31 / PSRM p340: ``PSET{axis}{data}``, data a constant or an expression. With
    P1 = 3 assigned on the line before, ``PSET X(P1+1)`` makes X 4 without motion."""
    _start(rig, ["TM100 TA10 TS0 X10", "P1=3", "PSET X(P1+1)"])
    _settle(rig)
    assert rig.c.positions(1) == {"X": 4.0}
    assert [f["positions"] for _, _, f in rig.events("pset")] == [{"X": 4.0}]


def test_a_pvt_end_velocity_may_be_an_expression(make_rig):
    """TSRM p463: ``X{pos}:{vel}``, the velocity a constant or an expression. ``X10:(P2)``
    with P2 = 100 is the same segment as ``X10:100``: the same positions through both
    segments (sampled every 20 cycles)."""
    paths = []
    for vel in ("100", "(P2)"):
        rig = make_rig()
        _start(rig, ["P2=100", f"ABS PVT100 X10:{vel}", "X20:0"])
        path = []
        for k in range(20, 480, 20):
            _run_to(rig, k)
            path.append(rig.c.positions(1)["X"])
        _settle(rig)
        assert rig.c.positions(1) == {"X": 20.0}
        paths.append(path)
    assert paths[1] == paths[0]
    assert 10.0 < paths[0][13] < 20.0  # (cycle 280: in the second segment)


def test_tsrm_p98_the_x_motors_ixx16_does_not_slow_a_move_of_y_alone(rig):
    """Ixx16 limits the motors of the axes that move: X is motor 1 with I116 = 0.1 cts/ms,
    Y motor 2 with I216 = 1000; ``Y10`` in TM100 (100 cts/ms of motor 2) keeps its 100 ms,
    the same as when X moves not at all (Y ends its stop Ta after TM from rest)."""
    rig.ok("&1 #1->1000X")
    rig.ok("&1 #2->1000Y")
    rig.ok("I117=1000")
    rig.ok("I217=1000")
    _start(rig, ["LINEAR ABS TM100 TA10 TS0 Y10"], "I116=0.1", "I216=1000")
    _settle(rig)
    assert rig.by_n("move_end")[1] - rig.by_n("move_start")[1] == math.ceil(
        rig.ms_cycles(110) - 1e-6
    )


def test_a_spline_point_waiting_through_a_feedrate_change_runs_at_the_new_rate(make_rig):
    """TSRM (%) / TUM p290: the time base scales every move still to run. X1 (ending in a
    stop) executes while ``SPLINE1 TM100 X2`` is calculated and waits for a next point;
    ``%50`` during X1 (reached at once) makes the series' move — X2 and the added segment to
    rest, closed when X1 has stopped — take twice as long as at %100."""
    durations = []
    for pct in ("%100", "%50"):
        rig = make_rig()
        _start(rig, ["TM200 TA100 TS0 X1"], "I5194=8388607")
        _run_to(rig, 50)
        rig.c.load_lines(1, ["SPLINE1 TM100 X2"])
        _run_to(rig, 100)
        assert 2 in rig.by_n("line_calculated") and 2 not in rig.by_n("move_start")
        rig.ok(pct)
        _settle(rig)
        durations.append(rig.by_n("move_end")[2] - rig.by_n("move_start")[2])
    assert durations[1] == 2 * durations[0]


# -- single step, holds and the I11 delay ---------------------------------------------------


def test_s_does_not_calculate_a_line_arriving_during_its_step(rig):
    """TSRM (S): one move, then the program stops. X2 arriving while the step's X1 executes
    is not calculated: only X1 runs and the program is stopped with X2 left in the buffer."""
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM100 TA10 TS0 X1"])
    rig.ok("S")
    _run_to(rig, 50)
    rig.c.load_lines(1, ["X2"])
    _settle(rig)
    assert sorted(rig.by_n("line_calculated")) == [1]
    assert sorted(rig.by_n("move_start")) == [1]
    assert rig.c.coord(1)["program"] == {"state": "stopped"}
    assert rig.c.rotary(1)["lines_ahead"] == 1


def test_r_on_an_empty_buffer_with_i11_waits_without_a_run_time_error(rig):
    """PUM p213: running out of lines is not an error. R on an empty rotary buffer with
    I11 = 20 ms: when the I11 time is up there is nothing to calculate; the program waits,
    and a line arriving later runs."""
    _start(rig, [], "I11=20")
    rig.run_for(0.1)
    assert rig.c.coord(1)["program"] == {"state": "waiting"}
    rig.c.load_lines(1, ["TM100 TA10 TS0 X1"])
    _settle(rig)
    assert "error" not in rig.c.coord(1)["program"]
    assert rig.c.positions(1) == {"X": 1.0}


def test_r_at_0_percent_calculates_the_first_move_and_starts_it_when_the_override_rises(rig):
    """TSRM (%): ``%0`` holds motion. R at %0 calculates the first move at the first RTI but
    it does not start; ``%100`` starts it at once."""
    _start(rig, ["TM100 TA10 TS0 X1"], "I5194=8388607", "%0")
    rig.run_for(0.1)
    assert 1 in rig.by_n("line_calculated") and rig.by_n("move_start") == {}
    k = rig.cyc(rig.cmd("%100").t_done)
    _settle(rig)
    assert rig.by_n("move_start") == {1: k}


@pytest.mark.parametrize("pct", ["%50", "%1"])
def test_a_feedrate_change_during_the_i11_delay_does_not_move_the_first_moves_start(rig, pct):
    """PSRM I11: the first move starts I11 (50 ms) after R. ``%50`` or ``%1`` given during
    the delay (reached at once) changes the speed, not the start: X1 starts when the delay is
    up (only ``%0`` holds it)."""
    _start(rig, ["TM100 TA10 TS0 X1"], "I5194=8388607", "I11=50")
    k_r = _states_at(rig)["running"]
    _run_to(rig, k_r + 20)
    rig.ok(pct)
    _settle(rig)
    assert rig.by_n("move_start")[1] == k_r + math.ceil(rig.ms_cycles(50) - 1e-9)


def test_a_pset_after_the_first_move_keeps_the_i11_delay_of_that_move(rig):
    """PSRM I11 / TUM p341: the first move of ``X1``, ``PSET X0`` (the PSET a lookahead
    break, calculated with it) still waits I11 = 50 ms after R; the PSET is no move of its
    own."""
    _start(rig, ["TM100 TA10 TS0 X1", "PSET X0"], "I11=50")
    k_r = _states_at(rig)["running"]
    _settle(rig)
    assert rig.by_n("move_start")[1] == k_r + math.ceil(rig.ms_cycles(50) - 1e-9)


# -- constant lines ---------------------------------------------------------------------------


def test_an_axis_first_named_on_a_later_constant_line_moves_from_0(rig):
    """An axis not yet commanded is at 0 and only its own line moves it: ``Y2`` after ``X1``
    ``X2`` moves Y from 0 to 2 once X has (nearly: the 10 ms blend) reached 2, ``Z3`` then Z
    from 0 to 3, ``X3`` X on from 2. Sampled every 5 cycles, every axis rises steadily from 0
    to its end point."""
    _start(rig, ["LINEAR ABS TM100 TA10 TS0 X1", "X2", "Y2", "Z3", "X3"])
    path = []
    for k in range(5, 1400, 5):
        _run_to(rig, k)
        pos = rig.c.positions(1)
        path.append(tuple(pos.get(a, 0.0) for a in "XYZ"))
    assert path[-1] == (3.0, 2.0, 3.0)
    assert all(y == z == 0.0 for x, y, z in path if x < 1.9)
    assert all(z == 0.0 for _, y, z in path if y < 1.9)
    for axis, end in enumerate((3.0, 2.0, 3.0)):
        values = [p[axis] for p in path]
        assert values == sorted(values)
        steps = [b - a for a, b in zip(values, values[1:], strict=False)]
        assert max(steps) < end / 10  # 100 ms moves: at most ~2.2 % of the way per 5 cycles


def test_inc_constant_lines_each_move_by_their_amount(rig):
    """TSRM (INC): axis words are distances from the last commanded point. ``X1`` three
    times after ``INC`` ends at X3."""
    _start(rig, ["LINEAR INC TM100 TA10 TS0 X1", "X1", "X1"])
    _settle(rig)
    assert rig.c.positions(1) == {"X": 3.0}
    assert sorted(rig.by_n("move_start")) == [1, 2, 3]


def test_a_run_time_error_in_calculation_aborts_the_program(rig):
    """TSRM p463: a PVT segment time computed outside (0, 4095.9998] ms is a run-time error:
    the program aborts with ``run_time_error`` at the RTI that calculates the line, nothing
    moves."""
    _start(rig, ["P1=0", "ABS PVT(P1) X1:0", "X2:0"])
    k = _next_rti(_states_at(rig)["running"])
    _settle(rig)
    assert rig.c.coord(1)["program"] == {"state": "aborted", "error": "run_time_error"}
    assert _states_at(rig)["aborted"] == k
    assert rig.by_n("move_start") == {}


def test_i11_shorter_than_the_wait_for_the_first_rti_is_a_run_time_error(rig):
    """PSRM I11 / TUM p339: the first move is due I11 after R and must be calculated by then.
    With I8 = 255 the first RTI is up to 256 cycles away; I11 = 10 ms (23 cycles) passes
    first: a run-time error at that instant, the line stays uncalculated, nothing moves."""
    _start(rig, ["TM100 TA10 TS0 X1"], "I8=255", "I11=10")
    k_r = _states_at(rig)["running"]
    _settle(rig)
    assert rig.c.coord(1)["program"] == {"state": "aborted", "error": "run_time_error"}
    assert _states_at(rig)["aborted"] == k_r + math.ceil(rig.ms_cycles(10) - 1e-9) < 256
    assert rig.by_n("line_calculated") == {} and rig.by_n("move_start") == {}


# -- more on depth and on settings changed on a line of their own ---------------------------------


def test_with_isx13_0_two_calculated_ahead_a_line_waits_for_the_rti_after_the_next_move_start(
    make_rig,
):
    """TUM p339: LINEAR with Isx13 = 0 keeps two moves calculated beyond the executing one.
    X1 executes with X2 and X3 calculated: X4 arriving one cycle before X2 starts is not
    wanted yet; X2's start asks for it, calculated at the first RTI strictly after that start
    (I8 = 0: the next cycle)."""

    def begin(rig: Rig) -> None:
        _start(rig, ["TM100 TA10 TS0 X1", "X2", "X3"], "I8=0")

    rig, k_s = _twin(make_rig, begin, lambda ref: ref.by_n("move_start")[2])
    rig.c.load_lines(1, ["X4"])
    _settle(rig)
    assert rig.by_n("move_start")[2] == k_s
    assert rig.by_n("line_calculated")[4] == k_s + 1


def test_segmented_linear_a_line_arriving_with_nothing_ahead_is_calculated_at_the_next_rti(rig):
    """TSRM p177: with Isx13 > 0 LINEAR keeps one move calculated beyond the executing one.
    X1 executes with nothing calculated after it: X2 arriving at cycle 100 is wanted at once,
    calculated at the next RTI, and X1 blends into it."""
    _start(rig, ["LINEAR ABS TM200 TA10 TS0 X1"], "I5113=10")
    _run_to(rig, 100)
    rig.c.load_lines(1, ["X2"])
    _settle(rig)
    assert rig.by_n("line_calculated")[2] == _next_rti(100)
    assert rig.by_n("move_start")[2] == rig.by_n("move_end")[1]


def test_a_pvt_time_set_on_a_line_of_its_own_applies_to_the_next_constant_segment(rig):
    """TSRM p463: ``PVT{t}`` sets the segment time of the segments after it. ``PVT50`` alone
    between 100 ms segments: the next constant segment takes 50 ms (on servo cycles)."""
    _start(rig, ["ABS PVT100 X10:100", "X20:100", "X30:100", "PVT50", "X35:0"])
    _settle(rig)
    starts, ends = rig.by_n("move_start"), rig.by_n("move_end")
    assert abs((ends[5] - starts[5]) - rig.ms_cycles(50)) <= 1
    assert abs((ends[3] - starts[3]) - rig.ms_cycles(100)) <= 1


def test_a_tm_set_on_a_line_of_its_own_applies_to_the_next_constant_move(rig):
    """TSRM (TM): the move time of the moves after it. ``TM300`` alone between TM100 moves
    (blended, TA10): the next constant move takes 300 ms from its start to the next one's."""
    _start(rig, ["LINEAR ABS TM100 TA10 TS0 X1", "X2", "X3", "TM300", "X4", "X5"])
    _settle(rig)
    starts = rig.by_n("move_start")
    assert abs((starts[6] - starts[5]) - rig.ms_cycles(300)) <= 1
    assert abs((starts[3] - starts[2]) - rig.ms_cycles(100)) <= 1


def test_tsrm_p98_ixx16_slows_every_move_of_a_stream_of_constant_lines(rig):
    """TSRM p98: with a motor on X, Ixx16 limits every LINEAR move, the streamed constant
    ones too. I116 = 20 cts/ms (20 units/s at 1000 cts/unit): each 10-unit TM100 move is
    stretched to 500 ms, start to start."""
    rig.ok("&1 #1->1000X")
    rig.ok("I117=1000")
    _start(rig, ["LINEAR ABS TM100 TA10 TS0 X10", "X20", "X30", "X40"], "I116=20")
    rig.run_until_idle(limit_s=5.0)
    starts = rig.by_n("move_start")
    for n in (2, 3):
        assert abs((starts[n + 1] - starts[n]) - rig.ms_cycles(500)) <= 1
