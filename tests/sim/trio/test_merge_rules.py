"""MERGE's conditions and its buffer steps, in virtual time on the event log.

Rules as written down in :mod:`motionsim.sim.trio.buffers` (MERGE: TRM entry ``[BK]``, spec §1.6,
§9.11): with MERGE ON on the base axis and the next move entering NTYPE before the MTYPE move
has begun its ramp down, the MTYPE move ends at speed and the next one starts from that speed;
only MOVE / MOVEABS / MOVECIRC / MHELICAL on the same axis group merge; at a merged joint the
next move takes over MTYPE in the servo period the first ends (``move_end`` and ``move_start``
both at ``e``), so MTYPE, VP_SPEED and MSPEED never read a stop while the axis runs on.
Axis settings as in conftest: MOVE(100) from rest to rest at period 1 ends at 111 (ramp down
from 101 on); one that ends at speed (merged) at 106.
"""

from __future__ import annotations

import pytest

from tests.sim.trio.conftest import cycle, fields, make, next_period, run_to


def _starts_ends(c, axis: int = 0) -> tuple[list[int], list[int]]:
    starts = [cycle(c, t) for t, _ in fields(c, "move_start", axis=axis)]
    ends = [cycle(c, t) for t, _ in fields(c, "move_end", axis=axis)]
    return starts, ends


def _merging(**axis0):
    c = make()
    c.set_axis(0, merge=1, **axis0)
    return c


def test_a_merged_move_takes_over_mtype_in_the_period_the_first_ends_and_spends_one_there():
    """MOVE(0.5) merged behind MOVE(100) with DECEL 10^7 needs only 0.55 ms from 1000 units/s
    to rest, less than a period: it takes over MTYPE at 106 (where the first ends) and ends at
    107, never in the period it started (UNITS 10: half a unit is 5 whole edges)."""
    c = _merging(decel=10_000_000, units=10)
    c.move(0, "MOVE", [100])
    next_period(c)
    c.move(0, "MOVE", [0.5])
    c.env.run()
    assert _starts_ends(c) == ([1, 106], [106, 107])
    assert c.axis(0)["dpos"] == pytest.approx(100.5)


def test_merge_needs_the_next_move_on_the_same_group_not_a_subset():
    """A 2-axis MOVE on BASE(0,1) followed by a MOVE of axis 0 alone: different axis groups,
    so the first ramps down to rest at 111 and the second starts from rest."""
    c = _merging()
    c.move(0, "MOVE", [100, 0])
    next_period(c)
    c.move(0, "MOVE", [100])
    c.env.run()
    assert _starts_ends(c) == ([1, 112], [111, 222])


def test_merge_needs_a_profiled_next_move():
    """FORWARD is not a velocity-profiled move with an end: MOVE(100) then FORWARD with MERGE
    ON stops in between as without MERGE."""
    c = _merging()
    c.move(0, "MOVE", [100])
    next_period(c)
    c.move(0, "FORWARD", [])
    run_to(c, 0.2)
    assert _starts_ends(c) == ([1, 112], [111])


def test_a_next_move_after_cancel_1_of_a_merged_one_is_not_merged():
    """CANCEL(1) of the move merged onto leaves the MTYPE move ending at speed (``[INF]``); a
    move entering NTYPE after that is not merged again: it starts at 107 from rest and takes
    the full 110 periods."""
    c = _merging()
    c.move(0, "MOVE", [100])
    next_period(c)
    c.move(0, "MOVE", [100])
    run_to(c, 0.0205)
    c.terminal("CANCEL(1) AXIS(0)")
    c.move(0, "MOVE", [100])
    c.env.run()
    assert _starts_ends(c) == ([1, 107], [106, 217])


def test_a_move_entering_ntype_as_the_ramp_down_would_begin_is_still_merged():
    """MOVE(100) would start its ramp down at period 101: a move entering NTYPE at 101 is in
    time (the first ends at speed at 106), one entering at 102 is too late (111)."""
    ends = []
    for issued in (0.1005, 0.1015):
        c = _merging()
        c.move(0, "MOVE", [100])
        run_to(c, issued)
        c.move(0, "MOVE", [10])
        c.env.run()
        ends.append(_starts_ends(c)[1][0])
    assert ends == [106, 111]
