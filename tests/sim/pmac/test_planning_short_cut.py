"""The planning short cut for streamed constant lines (``Planning._fast_kind``: LINEAR in time
mode, PVT) is a speed-up only: with it turned off every line takes the full calculation, and
the event log — every move, at every servo cycle — and the commanded path are the same."""

from __future__ import annotations

import re

import pytest
from motionsim.sim.pmac.lookahead.planning import Planning

from .conftest import Rig

PROGRAMS = {
    "linear_tm": (["LINEAR ABS TM100 TA20 TS0 X1", "X2 Y1", "X3", "Y5", "X0 Y0"], ()),
    "linear_tm_segmented": (["LINEAR ABS TM50 TA10 X1", "X2", "X2.5 Y1", "X4"], ("I5113=10",)),
    "linear_tm_50pct": (["LINEAR ABS TM80 TA30 X1", "X2", "X3"], ("%50",)),
    "linear_scurve": (["LINEAR ABS TM200 TA100 TS40 X1", "X3", "X2"], ()),
    "pvt": (["ABS PVT100 X10:100", "X20:100", "X30:0", "X25", "X20"], ()),
    "pvt_after_linear": (["LINEAR ABS TM100 TA10 X1", "PVT50 X2:10", "X3:0", "X4"], ()),
    "linear_after_pvt": (["ABS PVT50 X1:10", "X2:0", "LINEAR TM100 TA10 X3", "X4"], ()),
    "pvt_sync_writes": (["ABS PVT100 X10:100", "X15:100", "M1==1", "X20:100", "M1==2", "X30:0"],
                        ("M1->*",)),
    "linear_sync_writes": (["LINEAR ABS TM100 TA20 X1", "X2", "M1==1", "X3", "M1==2", "X4"],
                           ("M1->*",)),
    "linear_mode_line_after_pvt": (
        ["ABS PVT50 X1:10", "X2:10", "LINEAR", "X3", "PVT50 X4:0"], ()
    ),
}


def _log(monkeypatch: pytest.MonkeyPatch, lines: list[str], setup: tuple[str, ...],
         short_cut: bool) -> tuple[list, dict]:
    with monkeypatch.context() as m:
        if not short_cut:
            m.setattr(Planning, "_fast_kind", lambda self: 0)
        rig = Rig()
        rig.rotary_setup()
        for cmd in setup:
            rig.ok(cmd)
        rig.run_for(0.5)
        rig.c.load_lines(1, lines[:2])
        rig.ok("R")
        rig.run_for(0.12)
        rig.c.load_lines(1, lines[2:])  # streamed while the first moves run
        path = []
        for _ in range(600):  # the commanded positions every 5 ms for 3 s
            rig.run_for(0.005)
            path.append(rig.c.positions(1))
        rig.run_until_idle()
        events = [(e.t, e.type, dict(e.fields)) for e in rig.c.log.read(0, None).events]
        return events, path


@pytest.mark.parametrize("name", sorted(PROGRAMS))
def test_the_short_cut_plans_exactly_as_the_full_calculation(monkeypatch, name):
    lines, setup = PROGRAMS[name]
    fast = _log(monkeypatch, lines, setup, short_cut=True)
    full = _log(monkeypatch, lines, setup, short_cut=False)
    assert fast == full
    moves = [e for e in fast[0] if e[1] == "move_end"]
    assert len(moves) == sum(1 for line in lines if re.search(r"[XY]-?\d", line))
