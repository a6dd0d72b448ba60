"""The placement rule (MTYPE -> NTYPE -> process buffer) and the servo-period shuffle."""

from __future__ import annotations

import pytest
from motionsim.sim.errors import BufferFull, InvalidValue

from tests.sim.trio.conftest import cycle, fields, make, moves, next_period, run_to


@pytest.mark.parametrize(
    ("kind", "args", "code"),
    [
        ("MOVE", [10], 1),
        ("MOVEABS", [10], 2),
        ("MHELICAL", [0, 0, 5, 0, 0, 10], 3),
        ("MOVECIRC", [10, 0, 5, 0, 0], 4),
        ("FORWARD", [], 10),
        ("REVERSE", [], 11),
        ("DATUM", [1], 12),
    ],
)
def test_mtype_code_of_each_move_type(trio, kind, args, code):
    trio.move(0, kind, args)
    # M206-320: the move waits in the process buffer until the next servo interrupt
    assert (trio.axis(0)["mtype"], trio.pmove(0)) == (0, 1)
    run_to(trio, 0.0015)
    assert (trio.axis(0)["mtype"], trio.pmove(0)) == (code, 0)
    assert fields(trio, "move_start", axis=0) == [(0.001, {"axis": 0, "mtype": code})]


@pytest.mark.parametrize(
    ("line", "code"),
    [
        ("MOVE(10)", 1), ("MOVEABS(10)", 2), ("MHELICAL(0,0,5,0,0,10)", 3),
        ("MOVECIRC(10,0,5,0,1)", 4), ("FORWARD", 10), ("REVERSE", 11), ("DATUM(1)", 12),
    ],
)
def test_mtype_code_read_back_in_basic(trio, line, code):
    assert trio.terminal(f"{line} AXIS(2)").done
    assert trio.terminal("? MTYPE AXIS(2)").reply == "0.0000"  # still in the process buffer
    run_to(trio, 0.0015)
    assert trio.terminal("? MTYPE AXIS(2)").reply == f"{code}.0000"


def test_every_move_transits_the_process_buffer_then_mtype_ntype(trio):
    """M206-320 (PMOVE): a move goes into the process buffer first; the next servo interrupt
    moves it to NTYPE, and on to MTYPE when that is free, in the same interrupt."""
    assert moves(trio, 0, 3, [10]) == ["process_buffer"] * 3
    assert (trio.axis(0)["mtype"], trio.axis(0)["ntype"]) == (1, 1)
    assert trio.pmove(0) == 1  # the third waits for NTYPE
    with pytest.raises(BufferFull):
        trio.move(0, "MOVE", [10])
    pb = [(round(t * 1e3, 1), f["mtype"]) for t, f in fields(trio, "process_buffer")]
    assert pb == [(0.0, 1), (1.0, 0), (1.5, 1), (2.0, 0), (2.5, 1)]


def test_two_moves_in_one_servo_period_the_second_waits(trio):
    """The process buffer holds one move: a second move issued before the servo interrupt
    has transferred the first cannot be buffered (M206-320, TN20)."""
    assert trio.move(0, "MOVE", [10]) == "process_buffer"
    with pytest.raises(BufferFull):
        trio.move(1, "MOVE", [10])
    reply = trio.move(1, "MOVE", [10], wait=True)
    assert not reply.done
    run_to(trio, 0.0015)
    assert reply.done and reply.t_done == 0.001
    run_to(trio, 0.0025)
    starts = [(cycle(trio, t), f["axis"]) for t, f in fields(trio, "move_start")]
    assert starts == [(1, 0), (2, 1)]


def test_rejected_move_changes_nothing(trio):
    moves(trio, 0, 3, [10])
    before = (trio.axis(0), trio.terminal_state(), trio.log.last_seq)
    with pytest.raises(BufferFull):
        trio.move(1, "MOVE", [10])  # same process buffer, other axis: still full
    assert (trio.axis(0), trio.terminal_state(), trio.log.last_seq) == before
    assert trio.axis(1)["mtype"] == 0


def test_ntype_promoted_in_the_servo_period_after_the_move_ends(trio):
    trio.move(0, "MOVE", [10])  # 20 servo periods
    next_period(trio)
    trio.move(0, "MOVEABS", [0])
    run_to(trio, 0.1)
    end = [cycle(trio, t) for t, _ in fields(trio, "move_end", axis=0)]
    start = [cycle(trio, t) for t, _ in fields(trio, "move_start", axis=0)]
    assert start == [1, 22] and end == [21, 42]
    axis = [(cycle(trio, t), f["mtype"], f["ntype"]) for t, f in fields(trio, "axis", axis=0)]
    # the first move is sequenced and loaded in one interrupt: one change, straight to MTYPE
    assert axis == [(1, 1, 0), (2, 1, 2), (21, 0, 2), (22, 2, 0), (42, 0, 0)]
    assert trio.axis(0)["dpos"] == 0.0


def test_process_buffer_drains_two_periods_after_the_end(trio):
    moves(trio, 0, 3, [10])
    run_to(trio, 0.03)
    drained = fields(trio, "process_buffer", mtype=0)
    assert [cycle(trio, t) for t, _ in drained] == [1, 2, 23]


def test_multi_axis_move_occupies_every_axis_buffer(trio):
    trio.move(0, "MOVE", [10, 10])  # axes 0 and 1, interpolated
    next_period(trio)
    assert (trio.axis(0)["mtype"], trio.axis(1)["mtype"]) == (1, 1)
    trio.move(1, "MOVE", [5])
    next_period(trio)
    assert trio.axis(1)["ntype"] == 1  # axis 1 busy with the group move
    run_to(trio, 0.05)
    a0, a1 = trio.axis(0), trio.axis(1)
    assert a0["dpos"] == pytest.approx(10.0) and a1["dpos"] == pytest.approx(15.0)


def test_multi_axis_move_waits_for_every_ntype(trio):
    """Sequencing is all or nothing: the group move leaves the process buffer only when the
    NTYPE of both its axes is free."""
    moves(trio, 0, 2, [10])  # axis 0: MTYPE + NTYPE busy
    trio.move(0, "MOVE", [10, 10])  # axis 1 is free, axis 0 not
    run_to(trio, 0.1)
    pb_out = [cycle(trio, t) for t, _ in fields(trio, "process_buffer", mtype=0)]
    assert pb_out == [1, 2, 23]
    starts_axis1 = [cycle(trio, t) for t, _ in fields(trio, "move_start", axis=1)]
    assert starts_axis1 == [43]  # with the group move, after axis 0's second move


def test_wait_true_returns_when_the_process_buffer_frees(trio):
    moves(trio, 0, 3, [10])
    reply = trio.move(0, "MOVE", [10], wait=True)
    assert not reply.done
    run_to(trio, 0.05)
    assert reply.done and reply.reply == "process_buffer"
    assert reply.t_done == pytest.approx(0.023)


def test_moves_from_different_processes_use_their_own_process_buffers(trio):
    moves(trio, 0, 3, [10], process=0)
    assert trio.move(0, "MOVE", [10], process=1) == "process_buffer"
    with pytest.raises(BufferFull):
        trio.move(0, "MOVE", [10], process=1)


def test_bad_move_requests_are_validation_errors(trio):
    with pytest.raises(InvalidValue):
        trio.move(0, "JUMP", [1])
    with pytest.raises(InvalidValue):
        trio.move(0, "MOVECIRC", [1])
    with pytest.raises(InvalidValue):
        trio.move(7, "MOVE", [1, 2])  # needs axes 7 and 8; there are 8 axes
    assert trio.axis(0)["mtype"] == 0 and trio.log.last_seq == 0


def test_cancel_decelerates_and_loads_the_next_move(trio):
    trio.terminal("FORWARD AXIS(0)")
    trio.terminal("MOVE(5) AXIS(0)")
    run_to(trio, 0.1005)
    trio.terminal("CANCEL AXIS(0)")  # at speed 1000 -> 10 ms ramp at DECEL 100 000
    run_to(trio, 0.2)
    ends = [(cycle(trio, t), f["mtype"]) for t, f in fields(trio, "move_end", axis=0)]
    starts = [(cycle(trio, t), f["mtype"]) for t, f in fields(trio, "move_start", axis=0)]
    assert ends[0] == (110, 10)
    assert starts == [(1, 10), (111, 1)]
    assert trio.axis(0)["mtype"] == 0


def test_cancel_1_drops_only_the_ntype_move(trio):
    trio.terminal("MOVE(10) AXIS(0)")
    next_period(trio)
    trio.terminal("MOVE(10) AXIS(0)")
    next_period(trio)
    trio.terminal("CANCEL(1) AXIS(0)")
    assert (trio.axis(0)["mtype"], trio.axis(0)["ntype"]) == (1, 0)
    run_to(trio, 0.1)
    assert trio.axis(0)["dpos"] == 10.0


def test_rapidstop_cancels_every_axis_and_the_buffered_moves_then_load(trio):
    """RAPIDSTOP is CANCEL on every axis at once: the executing moves ramp down at DECEL, the
    moves in NTYPE and the process buffers stay and load next (spec §10.10 ``[INF]``: a
    production program issues RAPIDSTOP and then CANCEL again; the TRM page was not
    reachable)."""
    for line in ("FORWARD AXIS(1)", "MOVE(100) AXIS(0)", "MOVE(100) AXIS(0)"):
        trio.terminal(line)
        next_period(trio)
    run_to(trio, 0.05)
    trio.terminal("RAPIDSTOP")
    run_to(trio, 0.0615)
    stopped_at = trio.axis(0)["dpos"]
    assert trio.axis(1)["mtype"] == 0 and trio.axis(0)["mtype"] == 1  # the NTYPE move loaded
    run_to(trio, 0.5)
    ends = [(cycle(trio, t), f["mtype"]) for t, f in fields(trio, "move_end", axis=1)]
    assert ends == [(60, 10)]  # FORWARD: 10 ms ramp down from the cancel at period 50
    assert trio.axis(0)["dpos"] == pytest.approx(stopped_at + 100.0)


def test_rapidstop_2_also_empties_ntype_and_the_process_buffers(trio):
    for line in ("MOVE(100) AXIS(0)", "MOVE(100) AXIS(0)", "MOVE(100) AXIS(0)"):
        trio.terminal(line)
        next_period(trio)
    assert trio.terminal("? PMOVE").reply == "1.0000"
    run_to(trio, 0.05)
    trio.terminal("RAPIDSTOP(2)")
    assert trio.terminal("? PMOVE").reply == "0.0000"
    run_to(trio, 0.5)
    assert (trio.axis(0)["mtype"], trio.axis(0)["ntype"]) == (0, 0)
    assert len(fields(trio, "move_start", axis=0)) == 1
    assert trio.axis(0)["dpos"] < 100
    assert trio.terminal("RAPIDSTOP(1)").error.endswith("RAPIDSTOP(1) not simulated "
                                                        "(modes 0 and 2 are)")


def test_moveabs_target_from_where_the_axis_is_when_it_starts(trio):
    trio.terminal("MOVE(30) AXIS(3)")
    trio.terminal("MOVEABS(10) AXIS(3)")
    run_to(trio, 0.2)
    assert trio.axis(3)["dpos"] == 10.0


@pytest.mark.parametrize(("direction", "sign"), [(0, 1), (1, -1)])
def test_movecirc_turns_by_direction_and_ends_at_its_end_point(trio, direction, sign):
    """Start (0,0), centre (0,10), end (10,10): direction 0 turns positively (a quarter
    circle through x > 0), direction 1 negatively (three quarters through x < 0)."""
    trio.terminal("BASE(0,1)")
    trio.terminal(f"MOVECIRC(10,10,0,10,{direction})")
    run_to(trio, 0.01)
    assert sign * trio.axis(0)["dpos"] > 0 and trio.axis(1)["dpos"] > 0
    run_to(trio, 0.2)
    assert (trio.axis(0)["dpos"], trio.axis(1)["dpos"]) == (10.0, 10.0)


def test_dpos_endmove_remain_follow_the_profile(trio):
    trio.move(0, "MOVE", [200])  # starts at 1 ms, cruise at 1000 units/s from 11 ms
    run_to(trio, 0.0515)  # 50 ms into the move
    a = trio.axis(0)
    assert a["endmove"] == 200.0
    assert a["dpos"] == pytest.approx(5.0 + 40.0)
    assert a["remain"] == pytest.approx(155.0)
    run_to(trio, 0.3)
    assert trio.axis(0)["dpos"] == 200.0 and trio.axis(0)["remain"] == 0.0


def test_no_event_per_servo_period_during_a_long_move(trio):
    trio.move(0, "MOVE", [10_000])  # about 10 s
    run_to(trio, 5.0)
    # process_buffer in, process_buffer out, axis (MTYPE), move_start; nothing while it runs
    assert trio.log.last_seq == 4


def test_axis_parameters_checked_before_written(trio):
    with pytest.raises(InvalidValue):
        trio.set_axis(0, speed=50, accel=-1)
    assert trio.axis(0)["speed"] == 1000.0
    assert trio.set_axis(0, speed=50)["speed"] == 50.0


def test_units_rescales_the_user_position(trio):
    trio.move(0, "MOVE", [10])
    run_to(trio, 0.1)
    trio.set_axis(0, units=2)
    assert trio.axis(0)["dpos"] == 5.0


def test_config_rejects_unknown_keys():
    with pytest.raises(InvalidValue) as err:
        make(servo_hz=1000)
    assert err.value.details["field"] == "servo_hz"


def test_servo_period_config_quantises_move_starts():
    c = make(servo_period_ms=0.5)
    c.move(0, "MOVE", [10])
    run_to(c, 0.1)
    (start,), (end,) = fields(c, "move_start"), fields(c, "move_end")
    assert start[0] == 0.0005 and end[0] == pytest.approx(0.0205)
