"""Isx92 (move blend disable, read at ``R`` / ``S``): with Isx92 = 1 every move is a lookahead
break — the next line is calculated only once the move has stopped (TSRM Isx92). Changing it
while a program runs (``I5192=0`` and ``R`` during a move) must not leave that break standing
after the move stops: the program goes on with the following lines."""

from __future__ import annotations

import pytest


def test_isx92_cleared_and_r_during_a_move_lets_the_program_go_on(rig):
    rig.ok("I5192=1")
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM100 TA10 TS0 X1", "X2", "X3"])
    rig.ok("R")
    rig.run_for(0.05)
    assert [f["n"] for _, _, f in rig.events("move_start")] == [1]
    rig.ok("I5192=0")
    rig.ok("R")
    rig.run_until_idle(3.0)
    assert [f["n"] for _, _, f in rig.events("move_start")] == [1, 2, 3]
    assert rig.c.positions(1) == {"X": pytest.approx(3.0)}
    assert "error" not in rig.c.coord(1)["program"]
