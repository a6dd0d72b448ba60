"""Streamed LINEAR lines of a long ``TM`` under a feedrate override take ``TM`` × 100 / ``%``.

``TM`` is the move time in ms of a time-specified LINEAR move and is modal (TSRM p188-189,
p477; spec §9.1); the feedrate override ``%`` sets the coordinate system's time base, and
moves scale with it (TSRM p191, p260; spec §4.3): at ``%50`` every move takes twice its
programmed time. A run of blended identical moves starts one move every ``TM`` (spec §9.1,
N blended moves of TM each).

The lines after the first (``X2``, ``X3``: axis words with constant values only) take the
planning short cut for streamed lines (``Planning._fast_kind``), whose move time is the cached
``CoordState._tm_s``; its differential test (``test_planning_short_cut.py``) only streams
moves under one second. This file streams ``TM1500`` lines, above one second, at several
overrides and checks the absolute time of each move, so a short cut that scaled the time the
wrong way (or wrapped it at a second) fails here.
"""

from __future__ import annotations

import pytest
from motionsim.sim.pmac.buffers.rotary import RotaryBuffer

from .conftest import Rig

TM_MS = 1500.0


@pytest.mark.parametrize("override", [100.0, 50.0, 200.0])
def test_streamed_tm_lines_over_a_second_last_tm_times_100_over_the_override(
        monkeypatch: pytest.MonkeyPatch, override: float) -> None:
    taken_short: list[int] = []
    take_simple = RotaryBuffer.take_simple

    def spy(self: RotaryBuffer) -> int:
        n = take_simple(self)
        taken_short.append(n)
        return n

    monkeypatch.setattr(RotaryBuffer, "take_simple", spy)
    rig = Rig()
    rig.rotary_setup()
    rig.ok("I5194=8388607")  # Isx94 at its maximum: the new % is reached in one servo cycle
    rig.ok(f"%{override:g}")
    rig.c.load_lines(1, [f"LINEAR ABS TM{TM_MS:g} TA100 TS0 X1"])
    rig.ok("R")
    rig.run_for(0.2)
    rig.c.load_lines(1, ["X2", "X3", "X4"])  # streamed while the first move runs
    rig.run_until_idle()

    assert taken_short == [2, 3, 4]  # the streamed lines took the short cut
    starts = rig.by_n("move_start")
    expected = rig.ms_cycles(TM_MS * 100.0 / override)  # real time of one TM move
    for n in (2, 3):
        # moves start on servo cycles: within one cycle of the exact time
        assert abs(starts[n + 1] - starts[n] - expected) < 1.0
    assert abs(starts[4] - starts[2] - 2 * expected) < 1.0  # no drift over the run
    assert rig.c.positions(1)["X"] == pytest.approx(4.0)
