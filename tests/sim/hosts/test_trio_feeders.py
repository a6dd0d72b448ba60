"""Trio host feeders on the real Trio core: TN20's stall from the host side and its fix."""

from __future__ import annotations

from motionsim.app.scenarios.report import trio_report
from motionsim.sim.hosts import BlindFeeder, MovesBufferedFeeder, NtypeFeeder
from motionsim.sim.hosts.trio import Move, interleave, moves_buffered
from motionsim.sim.trio import TrioController

PER_AXIS = {0: [10] * 5, 1: [100] * 5}  # axis 0: 0.1 s moves, axis 1: 1 s moves


def feed(cls, **kw):
    trio = TrioController("trio")
    for axis in (0, 1):
        trio.set_axis(axis, speed=100)
    host = cls("h", trio, interleave(PER_AXIS), **kw)
    host.start()
    trio.env.run(until=7.0)
    return trio, host, trio_report(trio.log.events(), 7.0)


def test_interleave_follows_tn20_loop_order():
    assert interleave({0: [1, 2], 1: [3]}) == [
        Move(0, "MOVE", (1.0,)), Move(1, "MOVE", (3.0,)), Move(0, "MOVE", (2.0,))
    ]  # fmt: skip


def test_blind_feeder_blocks_and_axis_0_idles_while_it_waits():
    trio, host, rep = feed(BlindFeeder)
    assert host.issued == 10 and host.done_t is not None
    blocked = trio.log.events("host_blocked")
    assert blocked and all(e["process"] == 0 for e in blocked)
    assert rep["axes"][0]["idle_while_blocked_s"] > 0.5
    assert {s.cause for s in rep["starvation_list"]} == {"process_blocked_on_other_axis"}


def test_ntype_feeder_never_blocks_and_never_stalls_an_axis():
    trio, host, rep = feed(NtypeFeeder, poll_period_s=0.001)
    assert host.issued == 10
    assert trio.log.events("host_blocked") == []
    assert rep["idle_while_blocked_s"] == 0
    # axis 0 runs its five short moves back to back; fed blindly it finishes seconds later
    ends0 = [e.t for e in trio.log.events("move_end") if e["axis"] == 0]
    blind, _, _ = feed(BlindFeeder)
    blind_ends0 = [e.t for e in blind.log.events("move_end") if e["axis"] == 0]
    assert len(ends0) == len(blind_ends0) == 5
    assert ends0[-1] < 1.1 < 2.0 < blind_ends0[-1]


def test_moves_buffered_feeder_waits_below_the_limit():
    trio, host, rep = feed(MovesBufferedFeeder, max_buffered=1, poll_period_s=0.001)
    assert host.issued == 10
    # with at most one move held per axis a move only passes through the process buffer:
    # it leaves at the servo interrupt after it was written (M206-320)
    pb = trio.log.events("process_buffer")
    assert len(pb) == 20
    for fill, drain in zip(pb[::2], pb[1::2], strict=True):
        assert fill.fields["mtype"] == 1 and drain.fields["mtype"] == 0
        assert drain.t == trio.clock.t(trio.clock.after(fill.t))
    assert rep["axes"][0]["idle_while_blocked_s"] > 0.5  # still waits in program order


def test_moves_buffered_counts_mtype_and_ntype():
    assert moves_buffered({"mtype": 1, "ntype": 0}) == 1
    assert moves_buffered({"mtype": 1, "ntype": 2}) == 2
    assert moves_buffered({"moves_buffered": 7}) == 7
