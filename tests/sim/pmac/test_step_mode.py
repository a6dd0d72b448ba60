"""Isx53 step mode (TSRM p182): with Isx53 = 1 a step (``S``) executes one program line —
a line without a move too — and the program stops after it; with Isx53 = 0 (default) ``S``
runs through as many lines as it takes to reach the next move."""

from __future__ import annotations

PROG = ["P1=1", "P2=2", "LINEAR TA10 TS0 TM100 X10", "P3=3"]


def setup(rig, i53: int) -> None:
    rig.ok("#1->1000X")
    rig.ok(f"I5153={i53}")
    rig.ok("OPEN PROG 1 CLEAR")
    for line in PROG:
        rig.ok(line)
    rig.ok("CLOSE")
    rig.ok("&1 B1")


def step(rig) -> tuple[list[float], str, str]:
    rig.ok("&1 S")
    rig.run_until_idle(5.0)
    return ([rig.c.get_variable(f"P{j}") for j in (1, 2, 3)], rig.ok("#1P"),
            rig.c.coord(1)["program"]["state"])


def test_tsrm_p182_isx53_1_a_step_executes_one_program_line(rig):
    setup(rig, 1)
    assert step(rig) == ([1.0, 0.0, 0.0], "0", "stopped")
    assert step(rig) == ([1.0, 2.0, 0.0], "0", "stopped")
    assert step(rig) == ([1.0, 2.0, 0.0], "10000", "stopped")  # the move line
    assert step(rig) == ([1.0, 2.0, 3.0], "10000", "stopped")
    states = [f["state"] for _, _, f in rig.events("program")]
    assert states == ["running", "stopped"] * 4

