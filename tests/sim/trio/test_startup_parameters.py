"""The axis / system / process parameters a Trio start-up program sets and reads at line 1
(spec trio.md §10.11 "axis parameters" / "system" / "process" tables, §9.9, §9.10; power-up
values per sim/trio/axis_status.py and sim/trio/system.py, ``[BK]`` / ``[INF]`` where marked
there)."""

from __future__ import annotations

import pytest
from motionsim.sim.trio.card.axis_status import STORED_DEFAULTS

from tests.sim.trio.conftest import fields, make, run_to

STARTUP = """\
WDOG=OFF
BASE(0)
FS_LIMIT=5000
RS_LIMIT=-5000
ERRORMASK=268
AXIS_ENABLE=ON
SERVO=ON
FE_LIMIT=20 : FE_RANGE=10
JOGSPEED=50 : FASTDEC=20000
ATYPE AXIS(1)=44
IF SYSTEM_ERROR<>0 OR MOTION_ERROR<>0 THEN STOP
IF ERROR_AXIS<>-1 THEN STOP
WDOG=ON
OP(8,ON)
WHILE IN(0)=OFF AND MOTION_ERROR=0 AND VR(1)<3
  VR(1)=VR(1)+1
WEND
MOVE(100)
WAIT IDLE
VR(2)=AXISSTATUS
VR(3)=VERSION*100+CONTROL
OP(8,OFF)
"""


def test_startup_program_with_these_lines_runs_to_the_end():
    c = make()
    c.store_program("STARTUP", STARTUP)
    c.run_program("STARTUP", 1)
    run_to(c, 1.0)
    stopped = fields(c, "process", process=1, state="stopped")
    assert len(stopped) == 1 and "error" not in stopped[0][1]
    assert stopped[0][1]["line"] == STARTUP.count("\n")  # the last line ran
    assert c.get_variable("VR(1)") == 3.0
    assert c.get_variable("VR(2)") == 0.0  # idle, inside the limits
    assert c.get_variable("VR(3)") == pytest.approx(162 + 206, abs=1e-3)
    assert c.axis(0)["dpos"] == 100.0
    assert [f["on"] for _t, f in fields(c, "wdog")] == [True]  # WDOG=OFF at power-up: no event
    assert [(f["output"], f["value"]) for _t, f in fields(c, "output")] == [(8, 1), (8, 0)]
    for name, value in [("FS_LIMIT", 5000), ("RS_LIMIT", -5000), ("SERVO", 1), ("FE_LIMIT", 20),
                        ("FE_RANGE", 10), ("JOGSPEED", 50), ("FASTDEC", 20000)]:
        assert c.terminal(f"? {name} AXIS(0)").reply == f"{value:.4f}"
    assert c.terminal("? ATYPE AXIS(1)").reply == "44.0000"
    assert c.terminal("? ATYPE AXIS(0)").reply == "0.0000"


@pytest.mark.parametrize(("name", "reply"), [
    ("WDOG", "0.0000"), ("SYSTEM_ERROR", "0.0000"), ("MOTION_ERROR", "0.0000"),
    ("ERROR_AXIS", "-1.0000"), ("FREE", "47104.0000"), ("SERIAL_NUMBER", "0.0000"),
    ("SERVO_PERIOD", "1000.0000"), ("AXISSTATUS", "0.0000"), ("MSPEED", "0.0000"),
    ("VPSPEED", "0.0000"), ("RUN_ERROR", "0.0000"), ("ERROR_LINE", "0.0000"),
    ("FS_LIMIT", "200000000.0000"), ("RS_LIMIT", "-200000000.0000"),
    ("ERRORMASK", "268.0000"), ("FE_LIMIT", "2000.0000"), ("AXIS_ENABLE", "1.0000"),
])
def test_power_up_value_at_the_command_line(name, reply):
    c = make()
    r = c.terminal(f"?{name}")
    assert (r.reply, r.error) == (reply, None)


#: The power-up values docs/trio.md and sim/trio/parameters.py document (the gains: TRM
#: pp. 8-165, 8-171, 8-173; the others [BK]).
DOCUMENTED_POWER_UP = {
    "FS_LIMIT": 200_000_000, "RS_LIMIT": -200_000_000, "ERRORMASK": 268, "FE_LIMIT": 2000,
    "FE_RANGE": 0, "AXIS_ENABLE": 1, "SERVO": 0, "JOGSPEED": 0, "FASTDEC": 0, "ATYPE": 0,
    "P_GAIN": 1, "I_GAIN": 0, "D_GAIN": 0, "OV_GAIN": 0, "VFF_GAIN": 0, "DRIVE_STATUS": 0,
    "FE_LATCH": 0, "DATUM_IN": -1, "REP_DIST": 200_000_000, "REP_OPTION": 0, "CLUTCH_RATE": 0,
}


def test_stored_axis_parameters_have_the_documented_power_up_values():
    c = make()
    assert set(STORED_DEFAULTS) == set(DOCUMENTED_POWER_UP)
    for name, value in DOCUMENTED_POWER_UP.items():
        assert c.terminal(f"? {name} AXIS(3)").reply == f"{value:.4f}", name


@pytest.mark.parametrize(("cmd", "name", "reply"), [
    ("ERRORMASK=0", "ERRORMASK", "0.0000"), ("FE_RANGE=0.5", "FE_RANGE", "0.5000"),
    ("JOGSPEED=0", "JOGSPEED", "0.0000"),
])
def test_zero_and_fractions_are_accepted_where_negative_values_are_not(cmd, name, reply):
    c = make()
    assert c.terminal(cmd).error is None
    assert c.terminal(f"? {name}").reply == reply


@pytest.mark.parametrize(("model", "version", "control"), [
    ("series2", "1.4000", "216.0000"), ("mc2xx", "1.6200", "206.0000"),
    ("mc4xx", "2.0253", "464.0000"),
])
def test_version_and_control_follow_the_model(model, version, control):
    c = make(model=model)
    assert c.terminal("?VERSION").reply == version
    assert c.terminal("?CONTROL").reply == control


def test_wdog_written_from_the_command_line_logs_each_change_once():
    c = make()
    for cmd in ("WDOG=ON", "WDOG=ON", "WDOG=OFF", "WDOG=TRUE"):
        assert c.terminal(cmd).error is None
    assert c.terminal("?WDOG").reply == "1.0000"  # any non-zero value closes the relay
    assert [f["on"] for _t, f in fields(c, "wdog")] == [True, False, True]


def test_stored_parameters_are_per_axis_and_follow_base():
    c = make()
    c.terminal("FS_LIMIT AXIS(2)=123.5")
    c.terminal("BASE(2)")
    assert c.terminal("? FS_LIMIT").reply == "123.5000"
    assert c.terminal("? FS_LIMIT AXIS(0)").reply == "200000000.0000"


def test_switch_parameters_read_back_on_or_off():
    c = make()
    c.terminal("SERVO=TRUE")
    c.terminal("AXIS_ENABLE=0")
    assert c.terminal("? SERVO").reply == "1.0000"
    assert c.terminal("? AXIS_ENABLE").reply == "0.0000"


def test_negative_errormask_is_refused_and_changes_nothing():
    c = make()
    r = c.terminal("ERRORMASK=-1")
    assert r.error is not None and "ERRORMASK" in r.error
    assert c.terminal("? ERRORMASK").reply == "268.0000"


@pytest.mark.parametrize("name", ["VERSION", "CONTROL", "AXISSTATUS", "MOTION_ERROR", "MSPEED",
                                  "RUN_ERROR", "FREE"])
def test_read_only_parameters_cannot_be_written(name):
    c = make()
    r = c.terminal(f"{name}=5")
    assert r.error is not None and f"{name} cannot be written" in r.error


def test_power_cycle_restores_power_up_values():
    c = make()
    c.terminal("WDOG=ON")
    c.terminal("FS_LIMIT=10")
    c.terminal("OP(9,ON)")
    c.reset()
    assert c.terminal("?WDOG").reply == "0.0000"
    assert c.terminal("?FS_LIMIT").reply == "200000000.0000"
    assert c.terminal("?READ_OP(9)").reply == "0.0000"


def test_mspeed_and_vpspeed_are_the_demand_speed_while_moving():
    c = make()
    c.terminal("MOVE(500) AXIS(0)")
    run_to(c, 0.2)  # in the constant-speed part (SPEED 1000)
    assert c.terminal("? VP_SPEED").reply == "1000.0000"
    assert c.terminal("? MSPEED").reply == "1000.0000"
    assert c.terminal("? VPSPEED").reply == "1000.0000"


def test_run_error_and_error_line_hold_the_last_error_of_a_process():
    c = make()
    c.store_program("BAD", "VR(0)=1\nVR(1)=1/0\nVR(2)=3\n")
    c.store_program("PEEK", "VR(10)=RUN_ERROR PROC(2)\nVR(11)=ERROR_LINE PROC(2)\n")
    c.run_program("BAD", 2)
    run_to(c, 0.05)
    assert c.terminal("? RUN_ERROR PROC(2)").reply != "0.0000"
    assert c.terminal("? ERROR_LINE PROC(2)").reply == "2.0000"
    c.run_program("PEEK", 3)
    run_to(c, 0.1)
    assert c.get_variable("VR(11)") == 2.0 and c.get_variable("VR(10)") != 0.0
    assert c.terminal("? RUN_ERROR PROC(3)").reply == "0.0000"  # PEEK ended without error
    c.run_program("BAD", 2)  # a new run clears the error until it fails again
    assert c.terminal("? ERROR_LINE PROC(2)").reply == "0.0000"


@pytest.mark.parametrize("name, text", [("FS_LIMIT", "200000000.0000"),
                                        ("RS_LIMIT", "-200000000.0000")])
def test_a_64_bit_mc4xx_holds_the_software_limits_power_up_values_exactly(name, text):
    """On a 32-bit controller 2e8 +- 1 are one float32; an MC4xx's 64-bit word holds the
    power-up value 200000000 exactly (read back with 4 decimals)."""
    c = make(model="mc4xx")
    assert c.terminal(f"?{name}").reply == text
    c.terminal(f"{name}=200000001")
    assert c.terminal(f"?{name}").reply == "200000001.0000"


def test_rep_dist_is_held_in_edges_so_a_new_units_rescales_it():
    """TKB-REP: REP_DIST is stored as INT(value x UNITS): written as 100 with UNITS 1, it
    reads 10 after UNITS = 10 (the same 100 edges)."""
    from tests.sim.trio.conftest import make

    c = make()
    for line in ("UNITS=1", "REP_DIST=100", "UNITS=10"):
        assert c.terminal(line).error is None, line
    assert c.terminal("? REP_DIST").reply == "10.0000"
