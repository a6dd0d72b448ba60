"""An SP move runs at the FORCE_SPEED of its base axis (Trio BASIC MOVESP / FORCE_SPEED: the
speed of an SP move is FORCE_SPEED, a parameter of the base axis, taken when the move is
issued). Virtual time, from the move_end events."""

from __future__ import annotations

import pytest

from tests.sim.trio.conftest import fields, make, run_to


@pytest.mark.parametrize(("force_speeds", "seconds"), [((100, 50), 0.5), ((50, 100), 1.0)])
def test_movesp_takes_the_base_axis_force_speed(force_speeds, seconds):
    trio = make()
    for a in (0, 1):
        for cmd in (f"SPEED AXIS({a})=1000", f"ACCEL AXIS({a})=100000",
                    f"DECEL AXIS({a})=100000", f"FORCE_SPEED AXIS({a})={force_speeds[a]}"):
            assert trio.terminal(cmd).error is None, cmd
    trio.terminal("BASE(0,1)")
    assert trio.terminal("MOVESP(30,40)").error is None  # a vector of 50 units
    run_to(trio, 2.0)
    ends = [t for t, _f in fields(trio, "move_end")]
    assert len(ends) == 2
    # 50 units at FORCE_SPEED of axis 0, plus the short ramps (ACCEL / DECEL 100000)
    assert ends[0] == ends[1] == pytest.approx(seconds, abs=0.005)
