"""The placement rule's corner cases: group moves, waiting moves, CANCEL, SPEED, CONNECT.

Each test pins one rule of :mod:`motionsim.sim.trio.buffers` (module docstring; TRM MC206
p. 8-130 PMOVE (M206-320), TN20-16, TJ2P-21; spec §1.2, §1.6, §10.3, §10.5, §10.10) on the event
log, in virtual time. Axis settings (conftest): SPEED 1000, ACCEL = DECEL = 100 000 units/s²,
servo period 1 ms, so a MOVE(L) from rest to rest (L >= 10) takes 20 + (L - 10) periods, and a
move issued between periods ``k - 1`` and ``k`` starts at ``k`` when its buffers are free.
"""

from __future__ import annotations

import pytest

from tests.sim.trio.conftest import cycle, fields, make, moves, next_period, run_to


def _cycles(c, type_: str, **match) -> list[int]:
    return [cycle(c, t) for t, _ in fields(c, type_, **match)]


# -- waiting for the process buffer --------------------------------------------------------------


def test_a_waiting_move_with_room_in_its_process_buffer_is_placed_at_once(trio):
    """``wait`` only waits when the process buffer is full: with room the move is buffered at
    once (PMOVE = 1), exactly once, and runs from the next servo period."""
    reply = trio.move(0, "MOVE", [10], wait=True)
    assert (reply.done, reply.reply, reply.t_done) == (True, "process_buffer", 0.0)
    assert trio.pmove(0) == 1
    run_to(trio, 0.1)
    assert _cycles(trio, "move_start", axis=0) == [1]
    assert _cycles(trio, "move_end", axis=0) == [21]
    assert trio.axis(0)["dpos"] == pytest.approx(10.0)


def test_moves_waiting_for_one_process_buffer_are_placed_in_issue_order(trio):
    """A process' moves queue behind its one process buffer first come, first served: after
    RAPIDSTOP(2) emptied the buffer, a move issued next still waits behind the one that was
    already waiting (which is buffered at the next servo period, and moves on one later)."""
    moves(trio, 0, 3, [100], process=1)  # MTYPE, NTYPE, process buffer
    first = trio.move(0, "MOVE", [100], process=1, wait=True)
    assert not first.done
    assert trio.terminal("RAPIDSTOP(2)").done  # at 3.5 ms
    second = trio.move(1, "MOVE", [10], process=1, wait=True)
    assert not second.done
    run_to(trio, 0.0105)
    assert (cycle(trio, first.t_done), cycle(trio, second.t_done)) == (4, 5)
    assert _cycles(trio, "move_start", axis=1) == [6]


def test_a_withdrawn_waiting_move_gives_its_turn_to_the_next(trio):
    """Of two moves waiting for one process buffer, the first withdrawn: the second is buffered
    in the servo period where the buffer frees (23: TN20 promotion, two periods after the end
    of the MTYPE move at 21), and the withdrawn one never runs."""
    moves(trio, 0, 3, [10])
    first = trio.move(0, "MOVE", [10], wait=True)
    second = trio.move(0, "MOVE", [10], wait=True)
    assert trio.withdraw_move(first)
    run_to(trio, 0.2)
    assert not first.done and cycle(trio, second.t_done) == 23
    assert len(fields(trio, "move_start", axis=0)) == 4
    assert trio.axis(0)["dpos"] == pytest.approx(40.0)


# -- group moves: every axis or none -------------------------------------------------------------


@pytest.mark.parametrize("merge", [0, 1])
def test_a_group_move_waits_for_the_mtype_of_every_axis(merge):
    """An interpolated move loads into MTYPE only when the MTYPE of every axis it drives is
    free (TJ2P-21, spec §1.2): with axis 1 busy it waits in NTYPE of both axes, the move on
    axis 1 runs to its end untouched, and the group move starts in the next period (TN20).
    MERGE on the base axis changes nothing here (there is no move on axis 0 to merge with)."""
    c = make()
    c.set_axis(0, merge=merge)
    c.move(1, "MOVE", [100])  # axis 1: periods 1..111
    next_period(c)
    c.move(0, "MOVE", [10, 10])
    run_to(c, 0.0025)
    a0, a1 = c.axis(0), c.axis(1)
    assert (a0["mtype"], a0["ntype"], a1["mtype"], a1["ntype"]) == (0, 1, 1, 1)
    run_to(c, 0.5)
    assert [(cycle(c, t), f["mtype"]) for t, f in fields(c, "move_end", axis=1)][0] == (111, 1)
    assert _cycles(c, "move_start", axis=0) == [112]
    assert _cycles(c, "move_start", axis=1) == [1, 112]
    assert (c.axis(0)["dpos"], c.axis(1)["dpos"]) == pytest.approx((10.0, 110.0))


def test_a_group_move_waits_for_the_ntype_of_every_axis_not_only_its_base(trio):
    """Sequencing is all or nothing (M206-320): axis 0 is free but axis 1 has a move in NTYPE,
    so the group move stays in the process buffer until axis 1's NTYPE frees (its NTYPE move
    loads at 22, the group move is sequenced at 23) and axis 1's buffered move still runs."""
    moves(trio, 1, 2, [10])  # axis 1: MTYPE 1..21, NTYPE
    trio.move(0, "MOVE", [10, 10])
    run_to(trio, 0.2)
    assert _cycles(trio, "process_buffer", mtype=0) == [1, 2, 23]
    assert _cycles(trio, "move_start", axis=0) == [43]
    assert (trio.axis(0)["dpos"], trio.axis(1)["dpos"]) == pytest.approx((10.0, 30.0))


def test_process_buffer_events_of_a_group_move_name_its_base_axis(trio):
    """API.md ``process_buffer`` (``process``, ``axis``, ``mtype``): a group move on BASE(2,3)
    is reported on its base axis 2 when it enters the process buffer, when it leaves it for
    MTYPE or for NTYPE, and when RAPIDSTOP(2) empties the buffer."""
    for _ in range(3):
        trio.move(2, "MOVE", [10, 10])
        next_period(trio)
    trio.terminal("RAPIDSTOP(2)")  # at 3.5 ms: the third is still in the process buffer
    got = [(round(t * 1e4), f) for t, f in fields(trio, "process_buffer")]
    assert got == [
        (0, {"process": 0, "axis": 2, "mtype": 1}), (10, {"process": 0, "axis": 2, "mtype": 0}),
        (15, {"process": 0, "axis": 2, "mtype": 1}), (20, {"process": 0, "axis": 2, "mtype": 0}),
        (25, {"process": 0, "axis": 2, "mtype": 1}), (35, {"process": 0, "axis": 2, "mtype": 0}),
    ]
    assert trio.pmove(0) == 0


def test_idle_reads_true_once_the_moves_through_the_process_buffer_have_ended(trio):
    """IDLE AXIS(n): 0 while a move is on its way or running, TRUE (-1) when it has ended."""
    trio.terminal("MOVE(10) AXIS(0)")
    assert trio.terminal("? IDLE AXIS(0)").reply == "0.0000"
    run_to(trio, 0.0105)
    assert trio.terminal("? IDLE AXIS(0)").reply == "0.0000"
    run_to(trio, 0.05)
    assert trio.terminal("? IDLE AXIS(0)").reply == "-1.0000"
    trio.terminal("MOVE(10,10) AXIS(0)")
    run_to(trio, 0.1)
    assert [trio.terminal(f"? IDLE AXIS({n})").reply for n in (0, 1)] == ["-1.0000"] * 2


def test_sequencing_takes_the_process_buffers_in_process_number_order(trio):
    """Two processes' moves wait for one free NTYPE: the lower process number goes first
    (``[INF]``: the manuals do not say; the simulator keeps one fixed order so its logs are
    deterministic whatever order the moves arrived in)."""
    trio.move(0, "MOVE", [100])
    next_period(trio)
    trio.move(0, "MOVE", [10], process=2)
    trio.move(0, "MOVE", [20], process=1)
    run_to(trio, 0.3)
    out = [(cycle(trio, t), f["process"]) for t, f in fields(trio, "process_buffer", mtype=0)]
    assert out == [(1, 0), (2, 1), (113, 2)]
    assert trio.axis(0)["dpos"] == pytest.approx(130.0)


# -- CANCEL, CANCEL(1), RAPIDSTOP ----------------------------------------------------------------


def test_cancel_of_a_group_move_ramps_down_at_the_base_axis_decel(trio):
    """An interpolated move uses its base axis' profile parameters (spec §1.6, §10.5): CANCEL
    at 100.5 ms ramps it down from 1000 units/s at axis 0's DECEL (10 ms), not axis 1's."""
    trio.set_axis(1, decel=10_000)
    trio.move(0, "MOVE", [1000, 1000])
    run_to(trio, 0.1005)
    trio.terminal("CANCEL AXIS(0)")
    run_to(trio, 0.5)
    assert _cycles(trio, "move_end") == [110, 110]


def test_cancel_1_lets_the_process_buffer_refill_ntype_at_the_next_servo_period(trio):
    """CANCEL(1) empties NTYPE; the move waiting in the process buffer is sequenced into it at
    the next servo interrupt (spec §10.10 table), not when the MTYPE move ends."""
    moves(trio, 0, 3, [100])  # MTYPE, NTYPE, process buffer
    trio.terminal("CANCEL(1) AXIS(0)")  # at 3.5 ms
    assert (trio.axis(0)["ntype"], trio.pmove(0)) == (0, 1)
    run_to(trio, 0.0045)
    assert (trio.axis(0)["ntype"], trio.pmove(0)) == (1, 0)
    assert _cycles(trio, "process_buffer", mtype=0) == [1, 2, 4]


def test_cancel_of_a_linked_move_ends_it_at_the_next_servo_period(trio):
    """A move linked to another axis stops at once where it is (spec §10.10 ``[BK]``); its
    MTYPE empties at the next servo interrupt after the CANCEL (issued at 101.5 ms: 102)."""
    trio.terminal("CONNECT(1,0) AXIS(1)")
    next_period(trio)
    trio.terminal("FORWARD AXIS(0)")
    run_to(trio, 0.1015)
    trio.terminal("CANCEL AXIS(1)")
    run_to(trio, 0.2)
    assert [(cycle(trio, t), f["mtype"]) for t, f in fields(trio, "move_end", axis=1)] == [
        (102, 21)
    ]


def test_a_power_cycle_drops_the_moves_in_flight(trio):
    """Reset is a power cycle: moves running, buffered in NTYPE or a process buffer, or waiting
    for one, are gone; the log after the ``reset`` event has nothing from the buffers of
    before."""
    trio.move(0, "MOVE", [10])
    moves(trio, 1, 3, [10], process=1)
    trio.move(1, "MOVE", [10], process=1, wait=True)
    trio.reset()
    run_to(trio, 0.5)
    (reset,) = trio.log.events("reset")
    assert trio.log.last_seq == reset.seq
    assert (trio.axis(0)["dpos"], trio.axis(1)["dpos"]) == (0.0, 0.0)


# -- SPEED written while a move runs -------------------------------------------------------------


def test_speed_zero_holds_a_move_past_its_planned_end(trio):
    """SPEED = 0 holds the move in MTYPE (spec §10.5 pause idiom) however long: MOVE(100) was
    planned to end at 111; held from 50 ms, it is still loaded at 300 ms and ends only after
    SPEED is restored."""
    trio.move(0, "MOVE", [100])
    run_to(trio, 0.0505)
    trio.set_axis(0, speed=0)
    run_to(trio, 0.3)
    assert trio.axis(0)["mtype"] == 1 and fields(trio, "move_end") == []
    trio.set_axis(0, speed=1000)
    run_to(trio, 1.0)
    assert len(fields(trio, "move_end", axis=0)) == 1
    assert trio.axis(0)["dpos"] == pytest.approx(100.0)


def _group_move_end(speed_axis: int | None, at: float, sramp: float) -> tuple[int, float]:
    c = make()
    c.set_axis(0, sramp=sramp)
    c.move(0, "MOVE", [100, 100])
    run_to(c, at)
    if speed_axis is not None:
        c.set_axis(speed_axis, speed=500)
    run_to(c, at + 0.02)
    dpos = c.axis(0)["dpos"]
    run_to(c, 1.0)
    (end,) = set(_cycles(c, "move_end"))
    return end, dpos


@pytest.mark.parametrize(("at", "sramp"), [(0.0505, 0), (0.0035, 5)],
                         ids=["cruising", "in-the-s-ramp"])
def test_speed_of_a_group_move_is_its_base_axis_speed(at, sramp):
    """SPEED written on the base axis re-plans an interpolated move; written on another axis of
    the group it changes nothing, not even in the middle of an S ramp (spec §10.5: the base
    axis' values drive the group)."""
    plain = _group_move_end(None, at, sramp)
    assert _group_move_end(1, at, sramp) == plain
    assert _group_move_end(0, at, sramp)[0] > plain[0] + 50


def test_speed_written_during_a_cancel_does_not_restart_the_move(trio):
    """A cancelled move only ramps down: SPEED written during its ramp does not re-plan it to
    its old end: it stops where the CANCEL's ramp at DECEL takes it (from period 50, at 44 units:
    5 units on)."""
    trio.move(0, "MOVE", [100])
    run_to(trio, 0.0505)
    trio.terminal("CANCEL AXIS(0)")
    run_to(trio, 0.0525)
    trio.set_axis(0, speed=2000)
    run_to(trio, 0.3)
    assert _cycles(trio, "move_end", axis=0) == [60]
    assert trio.axis(0)["dpos"] == pytest.approx(44.0 + 5.0)


def test_a_move_shorter_than_a_servo_period_ends_at_the_next_one(trio):
    """A move takes whole servo periods (moves start and end on servo cycles): MOVE(0.001)
    starts at 1 and ends at 2."""
    trio.move(0, "MOVE", [0.001])
    run_to(trio, 0.01)
    assert (_cycles(trio, "move_start"), _cycles(trio, "move_end")) == ([1], [2])


def test_a_move_waiting_for_its_process_buffer_costs_no_servo_period_meanwhile(trio):
    """Only the servo periods where something can move on are simulated (DESIGN: the core
    jumps to the next cycle where something happens): while a move waits for a full process
    buffer behind a 10 s move, the next scheduled instant is that move's end."""
    moves(trio, 0, 2, [10_000])  # MTYPE 1..10011, NTYPE
    trio.move(0, "MOVE", [10_000])  # the process buffer
    trio.move(0, "MOVE", [10], wait=True)  # waits from before the next servo period
    run_to(trio, 0.0105)
    while trio.env.peek() <= trio.env.now:  # what is due now (the run's own stop) first
        trio.env.step()
    assert cycle(trio, trio.env.peek()) == 10_011


def test_stop_at_the_instant_a_wait_idle_is_satisfied_stops_the_program(trio):
    """STOP of a program whose WAIT IDLE was satisfied in this very servo period (the move
    ended at 21, the program not yet run on): the program stops there, without error."""
    trio.store_program("W", "MOVE(10) AXIS(0)\nWAIT IDLE AXIS(0)\nVR(1)=1\n")
    trio.run_program("W", 1)
    while not fields(trio, "move_end"):  # up to the servo period that ends the move
        trio.env.step()
    assert _cycles(trio, "move_end", axis=0) == [21]
    trio.stop_process(1)
    run_to(trio, 0.1)
    assert trio.get_variable("VR(1)") == 0.0 and trio.proc_status(1) == 0
