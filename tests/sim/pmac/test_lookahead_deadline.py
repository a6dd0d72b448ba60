"""The calculation deadline (TUM p339, p236; spec §4.1, §9.3): a program whose calculation falls
behind execution is aborted with a run-time error; running out of lines is not an error
(PUM p213, seed 000).

Moves here are ``TA1 TS0 TM1`` (Ta = TM = 1 ms). The default servo period is 442.7 µs and
the RTI comes every I8+1 = 3 servo cycles (1.33 ms): planning, requested once per move
start, cannot keep up with 1 ms moves.
"""

from __future__ import annotations

import math

HEADER = "LINEAR ABS TA1 TS0 TM1"  # line 1; the moves are lines 2, 3, ...


def ceil_cycles(rig, ms: float) -> int:
    return math.ceil(rig.ms_cycles(ms) - 1e-6)


def next_rti(k: int, m: int = 3) -> int:
    return (k // m + 1) * m


def _start(rig, lines):
    rig.rotary_setup()
    rig.c.load_lines(1, lines)
    rig.ok("R")
    k_r = rig.cyc(rig.c.now)
    return k_r


def _program(rig):
    return [(k, f) for k, _, f in rig.events("program")]


def test_1ms_moves_with_i8_2_abort_with_a_run_time_error_when_the_data_is_missing(rig):
    """TUM p339: "the time for the next move comes without the proper data in place ...
    Turbo PMAC will abort the program". With Isx13 = 0 a move's successor must be calculated
    when the move starts (2 moves ahead); 1 ms moves outrun one planning per 1.33 ms RTI."""
    k_r = _start(rig, [HEADER] + [f"X{i}" for i in range(1, 30)])
    rig.run_until_idle()
    k0 = next_rti(k_r)  # R's moves (lines 2-4) calculated and started at the first RTI
    # line 2 starts at k0 and blends into line 3 Ta/2 before its end (at 1 ms), line 3 into
    # line 4 at 2 ms; the planning that line 3's start asked for is due at the RTI after it
    k3, k4 = k0 + ceil_cycles(rig, 1), k0 + ceil_cycles(rig, 2)
    assert next_rti(k3) > k4  # ... too late for line 5, needed when line 4 starts
    starts = [(k, f["n"]) for k, _, f in rig.events("move_start")]
    assert starts == [(k0, 2), (k3, 3), (k4, 4)]
    assert _program(rig)[-1] == (k4, {"cs": 1, "state": "aborted", "error": "run_time_error"})
    # the stop is A's: decelerate at Ixx15 from the speed at that instant
    (k_end, _, end), = rig.events("move_end")[-1:]
    assert end == {"cs": 1, "n": 4} and k_end > k4
    calculated = [f["n"] for _, _, f in rig.events("line_calculated")]
    assert calculated == [1, 2, 3, 4]  # planning never caught up with line 5
    assert rig.c.coord(1)["program"] == {"state": "aborted", "error": "run_time_error"}
    assert rig.c.rotary(1)["lines_ahead"] == 26  # uncalculated lines stay, as after A


def test_run_time_error_sets_cs_status_word_2_bit_22_and_the_next_r_clears_it(rig):
    """TSRM p286 / PSRM ``??``: word 2 bit 22 "run-time error"; ``R`` starts afresh. At rest
    after the error in LINEAR mode (mode bits 000), word 2 is bit 22, the at-rest bit 17 and
    bit 16 (the rotary buffer is full: its uncalculated lines stay) and nothing else; word 3
    is 0."""
    _start(rig, [HEADER] + [f"X{i}" for i in range(1, 30)])
    rig.run_until_idle()
    status = rig.ok("??")
    assert rig.c.rotary(1)["full"]
    assert int(status[6:12], 16) == 1 << 22 | 1 << 17 | 1 << 16
    assert status[12:18] == "000000"
    rig.ok("I8=0")  # plan every servo cycle: now planning keeps up
    rig.ok("R")
    assert not int(rig.ok("??")[6:12], 16) & (1 << 22)
    assert "error" not in rig.c.coord(1)["program"]
    rig.run_until_idle()
    assert rig.events("move_end")[-1][2]["n"] == 30
    assert rig.c.coord(1)["program"] == {"state": "waiting"}


def test_run_time_error_clears_on_reset(rig):
    _start(rig, [HEADER] + [f"X{i}" for i in range(1, 30)])
    rig.run_until_idle()
    rig.c.reset()
    assert rig.c.coord(1)["program"] == {"state": "idle"}


def test_1ms_moves_with_i8_0_run_clean(make_rig):
    """I8 = 0: an RTI every servo cycle; each move's successor is calculated in time."""
    rig = make_rig(i8=0)
    _start(rig, [HEADER] + [f"X{i}" for i in range(1, 30)])
    rig.run_until_idle()
    assert [f["state"] for _, f in _program(rig)] == ["running", "waiting"]
    starts, ends = rig.events("move_start"), rig.events("move_end")
    assert [f["n"] for _, _, f in starts] == list(range(2, 31))
    # blended throughout: each move starts where the previous one ends, no stop in between
    assert [k for k, _, _ in ends[:-1]] == [k for k, _, _ in starts[1:]]
    assert ends[-1][0] - starts[0][0] == ceil_cycles(rig, 29 * 1 + 1)


def test_5ms_moves_with_i8_2_run_clean(rig):
    """5 ms moves leave planning several RTIs per move."""
    _start(rig, ["LINEAR ABS TA1 TS0 TM5"] + [f"X{i}" for i in range(1, 30)])
    rig.run_until_idle()
    assert [f["state"] for _, f in _program(rig)] == ["running", "waiting"]
    starts, ends = rig.events("move_start"), rig.events("move_end")
    assert [k for k, _, _ in ends[:-1]] == [k for k, _, _ in starts[1:]]
    assert ends[-1][0] - starts[0][0] == ceil_cycles(rig, 29 * 5 + 1)


def test_rotary_run_out_is_waiting_not_an_error(rig):
    """PUM p213: when the host stops sending, calculation catches up with the load point and
    the program suspends (``waiting``) — no run-time error, even with 1 ms moves."""
    k_r = _start(rig, [HEADER, "X1", "X2", "X3"])
    rig.run_until_idle()
    assert [f["state"] for _, f in _program(rig)] == ["running", "waiting"]
    assert int(rig.ok("??")[6:12], 16) & (1 << 22) == 0
    k0 = next_rti(k_r)
    assert rig.events("move_end")[-1][0] == k0 + ceil_cycles(rig, 3 * 1 + 1)


def test_a_line_arriving_after_planning_had_its_chance_is_a_run_out(rig):
    """The host is late, not the calculation: line 5 arrives after the RTI that last planned,
    so line 4 (Isx13 = 0) ends in a stop and line 5 starts from rest — no error."""
    k_r = _start(rig, [HEADER, "X1", "X2", "X3"])
    k0 = next_rti(k_r)
    k4 = k0 + ceil_cycles(rig, 2)  # line 4 starts; the last planning was at the RTI before
    assert next_rti(k0) < k4
    rig.run_for((k4 - 1) * rig.period - rig.c.now + 1e-9)
    rig.c.load_lines(1, ["X4"])
    rig.run_until_idle()
    assert [f["state"] for _, f in _program(rig)] == ["running", "waiting"]
    starts = {f["n"]: k for k, _, f in rig.events("move_start")}
    ends = {f["n"]: k for k, _, f in rig.events("move_end")}
    assert starts[5] == ends[4]  # from rest, after line 4's stop
    assert ends[4] == k0 + ceil_cycles(rig, 4)  # 3 blended moves + Ta, stopping


def test_segmented_mode_deadline_is_the_start_of_deceleration(make_rig):
    """Isx13 > 0: the successor is needed when the move's deceleration would begin (Ta/2 before
    its end); with 1 ms moves planning misses it there."""
    rig = make_rig(i5113=1)
    k_r = _start(rig, [HEADER] + [f"X{i}" for i in range(1, 30)])
    rig.run_until_idle()
    program = _program(rig)
    assert program[-1][1] == {"cs": 1, "state": "aborted", "error": "run_time_error"}
    k0 = next_rti(k_r)
    starts = [(k, f["n"]) for k, _, f in rig.events("move_start")]
    # line 3 starts at 1 ms; its deceleration would begin Ta/2 before its end (2 ms), before
    # the RTI that would have calculated line 4
    assert starts == [(k0, 2), (k0 + ceil_cycles(rig, 1), 3)]
    assert program[-1][0] == k0 + ceil_cycles(rig, 2) < next_rti(k0 + ceil_cycles(rig, 1))


def _run_at(rig, lines, k_before_r: int):
    """Load ``lines`` and send ``R`` ``k_before_r`` servo cycles into the run."""
    rig.rotary_setup()
    rig.c.load_lines(1, lines)
    if k_before_r:
        rig.run_for(k_before_r * rig.period)
    rig.ok("R")
    (k_r, _, f), = rig.events("program")
    assert f["state"] == "running"
    return k_r


def test_i11_shorter_than_the_wait_for_calculation_is_a_run_time_error(make_rig):
    """PSRM I11: the first move starts I11 ms after the run signal; calculated only at the
    next RTI (here I8 = 5: every 6 servo cycles), it is not ready when I11 = 1 ms is up."""
    rig = make_rig(i8=5, i11=1)
    k_r = _run_at(rig, ["TM10 TA1 TS0 X1", "X2"], 3)
    k_due = k_r + ceil_cycles(rig, 1)
    assert next_rti(k_r, 6) > k_due
    rig.run_until_idle()
    assert _program(rig) == [
        (k_r, {"cs": 1, "state": "running"}),
        (k_due, {"cs": 1, "state": "aborted", "error": "run_time_error"}),
    ]
    assert rig.events("move_start") == [] and rig.events("line_calculated") == []
    assert int(rig.ok("??")[6:12], 16) & (1 << 22)


def test_i11_long_enough_starts_the_first_move_i11_after_r(make_rig):
    rig = make_rig(i8=5, i11=3)
    k_r = _run_at(rig, ["TM10 TA1 TS0 X1", "X2"], 3)
    rig.run_until_idle()
    (k_calc, _, _), *_ = rig.events("line_calculated")
    (k_start, _, _), *_ = rig.events("move_start")
    assert k_calc == next_rti(k_r, 6) < k_start == k_r + ceil_cycles(rig, 3)
    assert [f["state"] for _, f in _program(rig)] == ["running", "waiting"]


def test_i11_with_an_empty_buffer_is_waiting_and_a_late_line_starts_i11_after_it(make_rig):
    """Nothing to calculate is a run-out, not a missed deadline: the I11 time counts from the
    line's arrival ("the move sent")."""
    rig = make_rig(i11=5)
    rig.rotary_setup()
    rig.ok("R")
    rig.run_for(40 * rig.period)
    assert [f["state"] for _, f in _program(rig)] == ["running", "waiting"]
    k_load = round(rig.c.now / rig.period)
    rig.c.load_lines(1, ["TM10 TA1 TS0 X1"])
    rig.run_until_idle()
    assert [f["state"] for _, f in _program(rig)] == ["running", "waiting", "running", "waiting"]
    (k_start, _, _), = rig.events("move_start")
    assert k_start == k_load + ceil_cycles(rig, 5)


def test_run_time_error_sets_the_motor_data_block_error_bit(rig):
    """PSRM ``?``: motor word 1 bit 14 "data block error" for a motor in the aborted CS."""
    rig.ok("&1 #1->1000X")
    rig.ok("&1 #2->1000Y")  # (not moved by the program, still in the CS)
    rig.ok("&2 #3->1000X")
    rig.ok("I116=2000")  # Ixx16 (TSRM p98) above 1000 counts/ms: the 1 ms moves keep their time
    rig.ok("I117=10000")  # and Ixx17 (PSRM p74) above 1000 counts/ms per ms, for the same reason
    _start(rig, [HEADER] + [f"X{i}" for i in range(1, 30)])
    rig.run_until_idle()

    def word1(motor: int) -> int:
        return int(rig.ok(f"#{motor}?")[:6], 16)

    assert word1(1) & (1 << 14) and word1(2) & (1 << 14)
    assert not word1(3) & (1 << 14)  # another coordinate system
    rig.ok("&1 I8=0 R")
    assert not word1(1) & (1 << 14)


def test_i11_too_short_for_a_line_arriving_while_waiting_is_a_run_time_error(make_rig):
    """The same deadline when the sequence is started by a line arriving (PSRM I11: "or the
    move sent if executing immediately")."""
    rig = make_rig(i8=5, i11=1)
    rig.rotary_setup()
    rig.ok("R")
    k = rig.cyc(rig.c.now)
    rig.run_for((next_rti(k, 6) - k) * rig.period + 1e-9)  # just past an RTI
    k_load = round(rig.c.now / rig.period)
    rig.c.load_lines(1, ["TM10 TA1 TS0 X1"])
    rig.run_until_idle()
    k_due = k_load + ceil_cycles(rig, 1)
    assert next_rti(k_load, 6) > k_due
    assert [(k, f["state"]) for k, f in _program(rig)] == [
        (k, "running"), (next_rti(k, 6), "waiting"), (k_due, "aborted")
    ]
    assert _program(rig)[-1][1]["error"] == "run_time_error"
    assert rig.events("move_start") == []


def test_the_last_line_in_the_buffer_when_planning_ran_is_a_deadline_miss_not_a_run_out(rig):
    """The boundary between the two: line 5 is the *last* line loaded, but it was in the
    buffer at every planning (loaded before R) and still not calculated when line 4 started:
    calculation fell behind — a run-time error exactly as with 30 lines, not ``waiting``."""
    k_r = _start(rig, [HEADER, "X1", "X2", "X3", "X4"])
    rig.run_until_idle()
    k0 = next_rti(k_r)
    k4 = k0 + ceil_cycles(rig, 2)
    assert [(k, f["n"]) for k, _, f in rig.events("move_start")] == [
        (k0, 2), (k0 + ceil_cycles(rig, 1), 3), (k4, 4)]
    assert _program(rig)[-1] == (k4, {"cs": 1, "state": "aborted", "error": "run_time_error"})
    assert rig.c.rotary(1)["lines_ahead"] == 1
