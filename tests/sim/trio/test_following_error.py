"""The following-error model and what a program's FE handling sees.

TRM MC216 listing p. 8-177 (SERVO): "If SERVO=ON the system software will compare the
difference between the DPOS and MPOS (FE) on the axis with the FE_LIMIT. If the difference
exceeds the limit the following error bit is set in the AXISSTATUS register, the enable relay is
forced OFF and the servo is set OFF." AXISSTATUS bit 8 = FE limit (spec §1.6); ERRORMASK
(power-up 268 = bits 2, 3, 8) decides which AXISSTATUS bits are a motion error (MOTION_ERROR,
ERROR_AXIS, the watchdog relay WDOG off); DATUM(0) clears it (spec §10.4, MC4 template).

The model (docs/trio.md "Following error", [INF]): MPOS follows DPOS ``fe_lag`` seconds behind,
so FE = fe_lag x the demand speed of the last servo period. conftest: SPEED 1000, ACCEL = DECEL
= 100 000 (10 ms ramps).
"""

from __future__ import annotations

import pytest
from motionsim.sim.errors import InvalidValue

from tests.sim.trio.conftest import fields, make, run_to


def num(c, expr: str) -> float:
    r = c.terminal(f"? {expr}")
    assert r.error is None, r.error
    return float(r.reply)


def test_fe_is_lag_times_speed_and_mpos_lags_dpos():
    c = make(fe_lag=0.002)
    assert num(c, "FE") == 0.0
    c.terminal("MOVE(100)")
    run_to(c, 0.05)  # cruising at 1000 units/s
    dpos, mpos = num(c, "DPOS"), num(c, "MPOS")
    assert num(c, "FE") == pytest.approx(2.0)
    assert dpos - mpos == pytest.approx(2.0)
    assert c.axis(0)["fe"] == pytest.approx(2.0) and c.axis(0)["mpos"] == pytest.approx(mpos)
    run_to(c, 0.5)  # at rest: MPOS has caught up
    assert num(c, "FE") == 0.0 and num(c, "MPOS") == 100.0


def test_no_lag_no_following_error():
    """The power-up plant follows exactly (MPOS = DPOS, as before the model)."""
    c = make()
    c.terminal("SERVO=ON")
    c.terminal("FE_LIMIT=0.001")
    c.terminal("MOVE(100)")
    run_to(c, 0.05)
    assert num(c, "FE") == 0.0 and num(c, "MPOS") == num(c, "DPOS")
    run_to(c, 0.5)
    assert fields(c, "following_error") == [] and num(c, "AXISSTATUS") == 0


def test_fe_range_sets_the_warning_bit_while_the_error_is_beyond_it():
    c = make(fe_lag=0.002)
    c.terminal("FE_RANGE=1")
    c.terminal("MOVE(100)")
    run_to(c, 0.05)
    assert int(num(c, "AXISSTATUS")) & 2 == 2  # FE 2 > FE_RANGE 1: bit 1 [BK]
    run_to(c, 0.5)
    assert int(num(c, "AXISSTATUS")) & 2 == 0


def test_fe_range_0_sets_no_warning_bit_whatever_the_error():
    """FE_RANGE = 0 (power-up, spec §10.11 [BK]) is no warning range: AXISSTATUS bit 1 stays
    clear while the axis lags (FE 2), as it does with no lag."""
    c = make(fe_lag=0.002)
    assert num(c, "FE_RANGE") == 0.0
    c.terminal("MOVE(100)")
    run_to(c, 0.05)
    assert num(c, "FE") == pytest.approx(2.0)
    assert int(num(c, "AXISSTATUS")) & 2 == 0


def _tripping(**config):
    c = make(fe_lag=0.002, **config)
    for line in ("SERVO=ON", "WDOG=ON", "FE_LIMIT=1.5"):
        assert c.terminal(line).error is None
    c.terminal("MOVE(100)")
    return c


def test_fe_beyond_fe_limit_trips_the_axis_and_raises_a_motion_error():
    c = _tripping()
    run_to(c, 0.5)
    trips = fields(c, "following_error")
    assert len(trips) == 1 and trips[0][1]["axis"] == 0 and trips[0][1]["fe"] > 1.5
    t_trip = trips[0][0]
    # 1.5 / 0.002 = 750 units/s, reached 7.5 ms into the 10 ms ramp (the move starts at 1 ms)
    assert 0.008 <= t_trip <= 0.010
    assert int(num(c, "AXISSTATUS")) & 256 == 256  # bit 8: FE limit
    assert num(c, "SERVO") == 0.0  # "the servo is set OFF"
    assert num(c, "WDOG") == 0.0  # "the enable relay is forced OFF"
    assert num(c, "MOTION_ERROR") == 1.0 and num(c, "ERROR_AXIS") == 0.0
    assert num(c, "FE_LATCH") == pytest.approx(trips[0][1]["fe"])
    assert [f for _t, f in fields(c, "wdog")] == [{"on": True}, {"on": False}]
    assert [(t, f["axis"]) for t, f in fields(c, "motion_error")] == [(t_trip, 0)]
    assert c.axis(0)["mtype"] == 0 and c.axis(0)["dpos"] < 5.0  # the move stopped there
    c.terminal("DATUM(0)")  # clears the motion error
    assert num(c, "MOTION_ERROR") == 0.0 and num(c, "ERROR_AXIS") == -1.0
    assert int(num(c, "AXISSTATUS")) & 256 == 0
    assert num(c, "WDOG") == 0.0  # the program switches the drives on again itself


def test_an_axis_already_in_motion_error_raises_no_second_one_and_another_axis_adds_its_bit():
    """A motion error is latched per axis until DATUM(0) (spec §10.4): axis 0 tripping again
    (SERVO and WDOG switched on again, moved again) drops WDOG again but raises no second
    motion error; axis 1 tripping then sets its own MOTION_ERROR bit (bit n for axis n
    ``[BK]``), ERROR_AXIS staying the first axis in error."""
    c = _tripping()
    run_to(c, 0.5)
    for line in ("SERVO=ON", "WDOG=ON", "MOVE(100)"):
        assert c.terminal(line).error is None
    run_to(c, 1.0)
    assert [f["axis"] for _t, f in fields(c, "following_error")] == [0, 0]
    assert [f["axis"] for _t, f in fields(c, "motion_error")] == [0]
    assert num(c, "MOTION_ERROR") == 1.0 and num(c, "WDOG") == 0.0
    for line in ("SERVO AXIS(1)=ON", "FE_LIMIT AXIS(1)=1.5", "WDOG=ON", "MOVE(100) AXIS(1)"):
        assert c.terminal(line).error is None, line
    run_to(c, 1.5)
    assert [f["axis"] for _t, f in fields(c, "motion_error")] == [0, 1]
    assert num(c, "MOTION_ERROR") == 3.0 and num(c, "ERROR_AXIS") == 0.0
    assert num(c, "WDOG") == 0.0


def test_with_servo_off_fe_is_not_compared_with_fe_limit():
    c = make(fe_lag=0.002)
    c.terminal("FE_LIMIT=1.5")
    c.terminal("MOVE(100)")
    run_to(c, 0.5)
    assert fields(c, "following_error") == [] and c.axis(0)["dpos"] == 100.0


def test_errormask_without_bit_8_trips_the_axis_but_raises_no_motion_error():
    c = _tripping()
    c.terminal("ERRORMASK=0")
    run_to(c, 0.5)
    assert len(fields(c, "following_error")) == 1
    assert int(num(c, "AXISSTATUS")) & 256 == 256 and num(c, "SERVO") == 0.0
    assert num(c, "MOTION_ERROR") == 0.0 and num(c, "WDOG") == 1.0
    assert fields(c, "motion_error") == []


def test_errormask_with_the_fs_limit_bit_makes_a_software_limit_a_motion_error():
    c = make()
    c.terminal("WDOG=ON")
    c.terminal("ERRORMASK=268+512")
    c.terminal("FS_LIMIT=50")
    c.terminal("MOVE(100) AXIS(0)")
    run_to(c, 0.5)
    assert [f["axis"] for _t, f in fields(c, "motion_error")] == [0]
    assert num(c, "MOTION_ERROR") == 1.0 and num(c, "WDOG") == 0.0
    d = make()  # power-up ERRORMASK: a software limit is not a motion error
    d.terminal("WDOG=ON")
    d.terminal("FS_LIMIT=50")
    d.terminal("MOVE(100)")
    run_to(d, 0.5)
    assert num(d, "MOTION_ERROR") == 0.0 and num(d, "WDOG") == 1.0


def test_a_programs_following_error_handler_runs_as_written():
    c = make(fe_lag=0.002)
    c.store_program("FEH", "\n".join([
        "SERVO=ON", "WDOG=ON", "FE_LIMIT=1.5", "MOVE(100)",
        "WAIT UNTIL MOTION_ERROR<>0",
        "VR(10)=ERROR_AXIS", "VR(11)=AXISSTATUS", "VR(12)=WDOG", "VR(13)=FE_LATCH",
        "DATUM(0)", "VR(14)=MOTION_ERROR",
        "SERVO=ON", "WDOG=ON", "FE_LIMIT=5", "MOVE(50)", "WAIT IDLE", "VR(15)=DPOS",
    ]) + "\n")
    c.run_program("FEH")
    run_to(c, 2.0)
    vr = [c.get_variable(f"VR({n})") for n in range(10, 16)]
    assert vr[0] == 0.0 and int(vr[1]) & 256 and vr[2] == 0.0 and vr[3] > 1.5
    assert vr[4] == 0.0
    assert vr[5] == pytest.approx(c.axis(0)["dpos"]) and c.axis(0)["mtype"] == 0
    assert fields(c, "following_error")[-1][1]["axis"] == 0 and len(
        fields(c, "following_error")) == 1  # FE 2 < FE_LIMIT 5 on the second move


def test_fe_lag_is_an_axis_setting_checked_on_write():
    c = make()
    assert c.set_axis(1, fe_lag=0.004)["fe_lag"] == 0.004
    with pytest.raises(InvalidValue):
        c.set_axis(1, fe_lag=-1)
    with pytest.raises(InvalidValue):
        c.set_axis(1, fe_lag=2)


def test_a_lag_set_while_the_axis_moves_is_watched_from_then_on():
    c = make()
    for line in ("SERVO=ON", "FE_LIMIT=1.5", "MOVE(100)"):
        c.terminal(line)
    run_to(c, 0.03)
    c.set_axis(0, fe_lag=0.002)  # FE 2 at 1000 units/s: beyond FE_LIMIT
    run_to(c, 0.5)
    assert [round(t, 6) for t, _f in fields(c, "following_error")] == [0.031]


def test_motion_errors_of_two_axes_set_one_bit_each_and_error_axis_names_the_first():
    """MOTION_ERROR holds one bit per axis in error (bit n for axis n), ERROR_AXIS the first
    axis that erred (spec §10.4): axes 2 and 3 trip their FE_LIMIT one after the other."""
    c = make(fe_lag=0.002)
    for line in ("WDOG=ON", "SERVO AXIS(2)=ON", "SERVO AXIS(3)=ON", "FE_LIMIT AXIS(2)=1.5",
                 "FE_LIMIT AXIS(3)=1.8", "MOVE(100) AXIS(2)", "MOVE(100) AXIS(3)"):
        assert c.terminal(line).error is None, line
    run_to(c, 0.5)
    assert [f["axis"] for _t, f in fields(c, "motion_error")] == [2, 3]  # once each
    assert num(c, "MOTION_ERROR") == 12.0 and num(c, "ERROR_AXIS") == 2.0
