"""Two behaviours no other test pinned, asserted on the event log in servo cycles.

* ``Q`` while a LINEAR move runs and the next line, a SPLINE1 point, waits for its successor
  (a spline point is moved only once the point after it is known, TUM p339 "2 moves ahead";
  spec §11.2): Q finishes the moves already calculated (PUM p213; spec §1 ``Q``) — the
  LINEAR move, to rest — and runs nothing more. The waiting point keeps its words in the
  rotary buffer; ``R`` then runs it as a one-point series, 3T (TUM p290: the added start and
  end segments).
* The blend between LINEAR moves of different TA, with the special lookahead active (Isx13 > 0,
  ``DEFINE LOOKAHEAD``, Isx20 > 0): each blend ramp is the *incoming* move's TA, centred on the
  programmed boundary (Quick Ref p49, TM between the ramps' centres; spec §9.1), and the final
  stop uses the TA in force after the last move line (PUM p175).
"""

from __future__ import annotations

import math

import pytest

from tests.sim.pmac.test_special_lookahead import _lookahead_setup
from tests.sim.pmac.test_special_lookahead import _run as _run_to_idle
from tests.sim.pmac.test_spline import _run, _states


def _cycles(rig, ms: float) -> int:
    """Servo cycles from a move start on a servo cycle to the first cycle at or after ``ms``."""
    return math.ceil(ms / 1000 / rig.period - 1e-6)


def test_pum_p213_q_during_linear_finishes_it_and_leaves_the_waiting_spline_point(rig):
    _run(rig, ["ABS LINEAR TA50 TS0 TM200 X10", "SPLINE1 TM100 X20"])
    rig.run_for(0.05)
    assert rig.by_n("move_start") == {1: rig.by_n("move_start")[1]}  # the LINEAR move runs
    rig.ok("Q")
    rig.run_for(0.5)
    start, end = rig.by_n("move_start"), rig.by_n("move_end")
    # the LINEAR move from rest: TM + TA = 250 ms, then stopped at that very cycle
    assert end == {1: start[1] + _cycles(rig, 250)}
    assert 2 not in start
    stopped = [k for k, _, f in rig.events("program") if f["state"] == "stopped"]
    assert stopped == [end[1]]
    assert rig.c.positions(1) == {"X": pytest.approx(10.0)}
    assert rig.c.rotary(1)["used_words"] > 0  # the waiting point's words are kept
    rig.ok("R")
    rig.run_for(1.0)
    start, end = rig.by_n("move_start"), rig.by_n("move_end")
    assert end[2] - start[2] == _cycles(rig, 300)  # a one-point series: 3T
    assert _states(rig) == ["running", "stopped", "running", "waiting"]
    assert rig.c.positions(1) == {"X": pytest.approx(20.0)}
    assert rig.c.rotary(1)["used_words"] == 0


@pytest.mark.parametrize("lookahead", [True, False])
def test_quick_ref_p49_the_blend_ramp_is_the_incoming_moves_ta_with_the_special_lookahead(
        rig, lookahead):
    """TA100 → TA200 → TA50, TM400 each: move 2 starts TA2/2 = 100 ms before its boundary
    (50 + 400 ms after the first motion), move 3 TA3/2 = 25 ms before its own (850 ms); the
    stop ends TA3/2 after the last boundary (1250 ms). Timed from the outgoing move's TA the
    starts would be 400 and 750 ms. Without the lookahead buffer the same times hold."""
    _lookahead_setup(rig, 10, "I116=100000", "I117=100000", lookahead=lookahead)
    assert (rig.c.coord_system(1).lookahead is not None) is lookahead
    _run_to_idle(rig, ["LINEAR INC TA100 TS0 TM400 X1", "TA200 TM400 X1", "TA50 TM400 X1"])
    start, end = rig.by_n("move_start"), rig.by_n("move_end")
    t0 = start[1]
    assert start[2] - t0 == _cycles(rig, 350)
    assert start[3] - t0 == _cycles(rig, 825)
    assert end[3] - t0 == _cycles(rig, 1275)
    assert (end[1], end[2]) == (start[2], start[3])  # each blend hands over at its start
