"""Order in the move buffers at the instants where it is easiest to get wrong.

TN20-16 and the TRM's MTYPE/NTYPE description: a move waits in NTYPE until the MTYPE move has
finished, then is pulled into MTYPE in the next servo period; a move issued meanwhile must
queue *behind* it (process buffer), never start ahead of it. A multi-axis (group) move needs
every one of its axes: it cannot take over an axis whose MTYPE still runs another move.
"""

from __future__ import annotations

import pytest

from tests.sim.trio.conftest import cycle, fields, next_period, run_to


def _runs(trio, axis: int) -> list[tuple[int, int]]:
    """``(start, end)`` servo periods of each move that ran on ``axis``, in order."""
    starts = [cycle(trio, t) for t, _ in fields(trio, "move_start", axis=axis)]
    ends = [cycle(trio, t) for t, _ in fields(trio, "move_end", axis=axis)]
    return list(zip(starts, ends, strict=True))


def test_a_move_issued_the_instant_mtype_ends_queues_behind_the_ntype_move(trio):
    """At the servo period where the MTYPE move ends, NTYPE still holds the next move (it is
    promoted in the following period): a move issued at that instant goes to the process
    buffer and runs third."""
    trio.move(0, "MOVE", [10])  # 20 servo periods
    next_period(trio)  # each move transits the process buffer (TRM p. 8-130)
    trio.move(0, "MOVE", [25])  # NTYPE: 35 servo periods
    t21 = 21 * trio.clock.period_s  # the first move ends in period 21: stop right after it
    run_to(trio, t21)
    while trio.env.peek() <= t21 + 1e-12 and not fields(trio, "move_end", axis=0):
        trio.env.step()
    assert [cycle(trio, t) for t, _ in fields(trio, "move_end", axis=0)] == [21]
    assert (trio.axis(0)["mtype"], trio.axis(0)["ntype"]) == (0, 1)
    assert trio.move(0, "MOVE", [1]) == "process_buffer"
    run_to(trio, 0.2)
    runs = _runs(trio, 0)
    assert [end - start for start, end in runs] == [20, 35, 7]  # 10, then 25, then 1 unit
    assert runs[1][0] == 22 and runs[2][0] == runs[1][1] + 1
    assert trio.axis(0)["dpos"] == pytest.approx(36.0)


def test_a_group_move_waits_for_the_mtype_move_on_one_of_its_axes(trio):
    """``MOVE(5,5)`` on axes 0 and 1 while axis 0 runs ``MOVE(10)``: the group move waits in
    NTYPE of both axes and starts on both in the period after axis 0's move ends; axis 0's
    own move is not overwritten (it runs its whole 10 units)."""
    trio.move(0, "MOVE", [10])
    next_period(trio)  # each move transits the process buffer (TRM p. 8-130)
    trio.move(0, "MOVE", [5, 5])
    next_period(trio)
    assert (trio.axis(0)["ntype"], trio.axis(1)["ntype"]) == (1, 1)
    assert (trio.axis(0)["mtype"], trio.axis(1)["mtype"]) == (1, 0)
    run_to(trio, 0.1)
    (first, group0) = _runs(trio, 0)
    (group1,) = _runs(trio, 1)
    assert first == (1, 21)
    assert group0[0] == group1[0] == 22
    assert trio.axis(0)["dpos"] == pytest.approx(15.0)
    assert trio.axis(1)["dpos"] == pytest.approx(5.0)
