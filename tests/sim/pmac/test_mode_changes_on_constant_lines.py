"""A change of move mode between streamed constant lines (axis words only, the mode set by an
earlier line) acts as it does on any other line: a SPLINE1 series ends, its last point run,
before the first LINEAR move (TUM p290: the series ends at another mode's move), and a LINEAR
move leaves no PVT velocity behind for the next PVT segment, which starts from its LINEAR
predecessor's end (TSRM p463: each segment's start velocity is the previous PVT segment's end
velocity)."""

from __future__ import annotations

import pytest


def _run(rig, lines: list[str]) -> dict[int, float]:
    """``lines`` in CS 1's rotary buffer, run to the end; each line's move start time."""
    rig.rotary_setup()
    rig.c.load_lines(1, lines)
    rig.ok("R")
    rig.run_until_idle(limit_s=5.0)
    return {f["n"]: k * rig.period for k, _, f in rig.events("move_start")}


def test_a_spline_series_runs_its_last_point_before_a_linear_constant_line(make_rig):
    """``SPLINE1 ... X1``, ``X2``, ``LINEAR``, ``X5``: the move to X5 starts after the move to
    X2 (the series' last point), and X ends at 5."""
    rig = make_rig(i8=0)
    starts = _run(rig, ["SPLINE1 TM100 ABS X1", "X2", "LINEAR", "X5"])
    assert list(starts) == [1, 2, 4]
    assert starts[1] < starts[2] < starts[4]
    assert rig.c.positions(1) == {"X": pytest.approx(5.0)}


def test_a_pvt_segment_after_a_linear_constant_line_starts_from_rest(make_rig):
    """PVT to X10 at 50 units/s, LINEAR to X20, then ``PVT100 X30:0``: the last segment joins
    X20 at rest to X30 at rest, so at half its time X is halfway, 25 (a start velocity left
    from the first PVT segment would bend the cubic away from the midpoint)."""
    rig = make_rig(i8=0)
    rig.rotary_setup()
    rig.c.load_lines(1, ["PVT100 ABS", "X10:50", "LINEAR TM100 TA10 TS0", "X20",
                         "PVT100 X30:0"])
    rig.ok("R")
    while not [f for _, _, f in rig.events("move_start") if f["n"] == 5]:
        rig.c.env.step()
    rig.run_for(0.05)
    assert rig.c.positions(1)["X"] == pytest.approx(25.0)
    rig.run_for(0.06)
    assert rig.c.positions(1)["X"] == pytest.approx(30.0)
