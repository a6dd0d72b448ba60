"""A PLC cannot flood the card's command queue (issue 33 item 2; TSRM p423-424).

"If there is no room for a new command, program execution is temporarily halted until the new
command can be placed on the queue" (TSRM p423): the queue of program-issued commands holds
``CAPACITY`` commands; a PLC issuing more per scan than the interpreter takes (one per
background cycle) is halted, not grown without bound; ``DISABLE PLC`` from the host, CTRL-D
and a reset end its queued work. Virtual time; counts, never durations.
"""

from __future__ import annotations

from motionsim.sim.pmac.tasks.command_queue import CAPACITY

from tests.sim.pmac.test_plc import enter

FLOOD = [f'CMD"P{100 + k}=P{100 + k}+1"' for k in range(100)] + ["P1=P1+1"]


def _queued(rig) -> int:
    return len(rig.c.background.queue)


def _commands_run(rig) -> int:
    return int(sum(rig.c.get_variable(f"P{100 + k}") for k in range(100)))


def test_capacity_is_32_commands() -> None:
    assert CAPACITY == 32


def test_a_flooding_plc_is_halted_at_the_bounded_queue(make_rig):
    """100 CMDs per scan: the queue never holds more than CAPACITY program commands, the PLC
    scans only when its commands fit, and every command issued runs exactly once in order."""
    rig = make_rig(i5=2)
    enter(rig, *FLOOD, n=1)
    rig.ok("ENABLE PLC 1")
    peak = 0
    for _ in range(200):
        rig.run_for(0.002)
        peak = max(peak, _queued(rig), rig.c.commands.queued)
    assert peak <= CAPACITY
    scans = int(rig.c.get_variable("P1"))
    assert scans >= 2
    issued = scans * 100
    waiting = rig.c.commands.waiting() + rig.c.commands.queued
    # nothing lost or duplicated: what ran plus what still waits is what was issued
    assert _commands_run(rig) + waiting == issued
    assert waiting <= 100 + CAPACITY


def test_host_commands_are_still_answered_during_the_flood(make_rig):
    rig = make_rig(i5=2)
    enter(rig, *FLOOD, n=1)
    rig.ok("ENABLE PLC 1")
    rig.run_for(1.0)
    assert rig.ok("P2=42 P2") == "42"
    assert _queued(rig) <= CAPACITY + 1


def test_host_disable_plc_ends_its_queued_and_waiting_commands(make_rig):
    rig = make_rig(i5=2)
    enter(rig, *FLOOD, n=1)
    rig.ok("ENABLE PLC 1")
    rig.run_for(0.5)
    rig.ok("DISABLE PLC 1")
    ran = _commands_run(rig)
    rig.run_for(0.5)
    assert _commands_run(rig) == ran  # nothing of PLC 1 ran after its DISABLE
    assert rig.c.commands.waiting() == 0
    assert rig.c.commands.queued == 0
    assert _queued(rig) == 0


def test_ctrl_d_and_reset_end_the_queued_work(make_rig):
    rig = make_rig(i5=2)
    enter(rig, *FLOOD, n=1)
    rig.ok("ENABLE PLC 1")
    rig.run_for(0.3)
    rig.ok("\x04")  # <CTRL-D>: disable all PLCs
    ran = _commands_run(rig)
    rig.run_for(0.3)
    assert _commands_run(rig) == ran and rig.c.commands.waiting() == 0
    rig.ok("ENABLE PLC 1")
    rig.run_for(0.3)
    rig.c.reset()
    assert rig.c.commands.waiting() == 0 and _queued(rig) == 0


def test_a_plcs_own_disable_keeps_what_it_issued(make_rig):
    """The init-PLC idiom: CMDs then DISABLE PLC 1 in the same scan — every command runs."""
    rig = make_rig(i5=2)
    enter(rig, *[f'CMD"P{200 + k}=1"' for k in range(40)], "DISABLE PLC 1", n=1)
    rig.ok("ENABLE PLC 1")
    rig.run_for(0.5)
    assert [rig.c.get_variable(f"P{200 + k}") for k in range(40)] == [1.0] * 40
    assert rig.c.plcs.to_list()[0]["enabled"] is False
