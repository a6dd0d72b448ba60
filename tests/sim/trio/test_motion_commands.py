"""Motion commands beyond MOVE / MOVEABS: their MTYPE codes, the SP moves, MOVEMODIFY,
DEFPOS / OFFPOS, SPEED / ACCEL / DECEL written while a move runs, CANCEL with an S-ramp.

Sources per test: MTYPE codes spec §10.1 (TN20, TJ2P-20 and two third-party enums); SP moves
and MOVEMODIFY spec §10.2; DEFPOS / OFFPOS TRM MC216 listing p. 220 ("take effect at the next
servo update"); SPEED during a move TRM MC206 p. 8-17 ("the speed may be changed at any time")
and spec §10.5. Axis settings (conftest): SPEED 1000, ACCEL = DECEL = 100 000 units/s²: 10 ms
ramps of 5 units.
"""

from __future__ import annotations

import pytest

from tests.sim.trio.conftest import cycle, fields, make, next_period, run_to


def _program(c, text: str, process: int = 1) -> None:
    c.store_program("P", text)
    c.run_program("P", process)


@pytest.mark.parametrize(
    ("line", "code"),
    [
        ("MOVEMODIFY(10)", 5), ("MOVESP(10)", 6), ("MOVEABSSP(10)", 7),
        ("MOVECIRCSP(10,0,5,0,0)", 8), ("MHELICALSP(0,0,5,0,0,10)", 9),
        ("CAM(0,1,1,10)", 13), ("CAMBOX(0,1,1,10,3)", 20), ("CONNECT(1,3)", 21),
        ("MOVELINK(10,10,0,0,3)", 22),
    ],
)
def test_mtype_codes_of_the_chapter_8_motion_commands(trio, line, code):
    """Each command transits the process buffer and reports its code in MTYPE (spec §10.1)."""
    trio.set_variable("TABLE(1)", 10)
    assert trio.terminal(f"{line} AXIS(0)").error is None
    run_to(trio, 0.0015)
    assert trio.terminal("? MTYPE AXIS(0)").reply == f"{code}.0000"
    assert fields(trio, "move_start", axis=0) == [(0.001, {"axis": 0, "mtype": code})]


def test_aliases_co_and_ml_are_connect_and_movelink(trio):
    assert trio.terminal("CO(1,3) AXIS(0)").error is None
    run_to(trio, 0.0015)
    assert trio.axis(0)["mtype"] == 21


# -- SPEED, ACCEL, DECEL while a move runs ---------------------------------------------------


def test_speed_written_during_forward_changes_the_running_move(trio):
    """The report's bug: SPEED written during FORWARD left the axis at the old speed. The
    profile ramps at DECEL from 1000 to the new 500 units/s from the servo period of the
    write (spec §10.5), MTYPE stays FORWARD."""
    trio.terminal("FORWARD AXIS(0)")
    run_to(trio, 0.1005)
    assert trio.axis(0)["vp_speed"] == pytest.approx(1000.0)
    trio.terminal("SPEED AXIS(0)=500")
    run_to(trio, 0.2005)
    a = trio.axis(0)
    assert a["vp_speed"] == pytest.approx(500.0) and a["mtype"] == 10
    d0 = a["dpos"]
    run_to(trio, 0.3005)
    assert trio.axis(0)["dpos"] - d0 == pytest.approx(50.0)  # 0.1 s at 500 units/s


def test_speed_zero_holds_the_move_in_mtype_and_restoring_it_resumes(trio):
    """The pause idiom of a production program (spec §10.5): SPEED=0 ramps the move down at
    DECEL and holds it, MTYPE still loaded; SPEED restored, it runs on to its end."""
    trio.move(0, "MOVE", [1000])  # 1.01 s at 1000 units/s
    run_to(trio, 0.2005)
    trio.set_axis(0, speed=0)
    run_to(trio, 0.25)
    held = trio.axis(0)["dpos"]
    run_to(trio, 0.5005)
    a = trio.axis(0)
    assert (a["dpos"], a["mtype"], a["vp_speed"]) == (held, 1, 0.0)
    assert a["remain"] == pytest.approx(1000.0 - held)
    trio.set_axis(0, speed=1000)
    run_to(trio, 2.0)
    (end,) = [cycle(trio, t) for t, _ in fields(trio, "move_end", axis=0)]
    assert trio.axis(0)["dpos"] == pytest.approx(1000.0)
    # 1011 periods; stopped from 210 (end of the ramp down) to 500; the two extra ramps run
    # 10 units at half speed: 10 periods more
    assert end == pytest.approx(1011 + 290 + 10, abs=1)


def test_decel_written_during_a_move_shapes_its_end(trio):
    trio.move(0, "MOVE", [200])  # ends at period 211 with DECEL 100 000
    run_to(trio, 0.1005)
    trio.set_axis(0, decel=10_000)  # ramp down now takes 100 ms (50 units)
    run_to(trio, 1.0)
    (end,) = [cycle(trio, t) for t, _ in fields(trio, "move_end", axis=0)]
    assert end == 211 + 45 and trio.axis(0)["dpos"] == pytest.approx(200.0)


# -- SP moves --------------------------------------------------------------------------------


def test_movesp_runs_at_force_speed_captured_when_issued(trio):
    """MOVESP keeps the FORCE_SPEED it was issued with, whatever FORCE_SPEED or SPEED are
    later (spec §10.2 ``[BK]``): 100 units at 200 units/s with 2 ms ramps = 502 periods."""
    trio.terminal("FORCE_SPEED AXIS(0)=200")
    trio.terminal("MOVESP(100) AXIS(0)")
    trio.terminal("FORCE_SPEED AXIS(0)=1000")
    run_to(trio, 0.1)
    trio.set_axis(0, speed=50)
    run_to(trio, 1.0)
    ((start, _),) = [(cycle(trio, t), f) for t, f in fields(trio, "move_start", axis=0)]
    ((end, _),) = [(cycle(trio, t), f) for t, f in fields(trio, "move_end", axis=0)]
    assert (start, end) == (1, 503)
    assert trio.axis(0)["dpos"] == pytest.approx(100.0)


def test_moveabssp_and_movecircsp_have_the_geometry_of_their_plain_moves(trio):
    trio.terminal("MOVEABSSP(30) AXIS(0)")
    run_to(trio, 0.5)
    assert trio.axis(0)["dpos"] == pytest.approx(30.0)
    trio.terminal("BASE(2,3)")
    trio.terminal("MOVECIRCSP(10,10,0,10,0)")
    run_to(trio, 1.0)
    assert (trio.axis(2)["dpos"], trio.axis(3)["dpos"]) == pytest.approx((10.0, 10.0))


# -- MOVEMODIFY ------------------------------------------------------------------------------


def test_movemodify_moves_the_end_of_the_executing_move(trio):
    """MOVEMODIFY(200) while MOVEABS(100) runs: the same move (one move_end, MTYPE 2) now ends
    at 200; the MOVEMODIFY itself never reaches MTYPE (spec §10.2)."""
    trio.move(0, "MOVEABS", [100])
    run_to(trio, 0.0505)
    trio.move(0, "MOVEMODIFY", [200])
    run_to(trio, 0.0515)
    assert trio.axis(0)["endmove"] == 200.0 and trio.axis(0)["mtype"] == 2
    run_to(trio, 1.0)
    assert [f["mtype"] for _, f in fields(trio, "move_start", axis=0)] == [2]
    assert [f["mtype"] for _, f in fields(trio, "move_end", axis=0)] == [2]
    assert [(cycle(trio, t), f) for t, f in fields(trio, "move_modify")] == [
        (51, {"axis": 0, "mtype": 2, "end": 200.0})
    ]
    assert trio.axis(0)["dpos"] == pytest.approx(200.0)


def test_movemodify_shortens_the_move_ahead(trio):
    trio.move(0, "MOVE", [100])
    run_to(trio, 0.0305)  # at 25 units, cruising
    trio.move(0, "MOVEMODIFY", [40])
    run_to(trio, 1.0)
    ends = [cycle(trio, t) for t, _ in fields(trio, "move_end", axis=0)]
    assert trio.axis(0)["dpos"] == pytest.approx(40.0) and len(ends) == 1
    assert ends[0] == 51  # 31 + 15 units at speed (10 ms) + the 10 ms ramp down


def test_movemodify_behind_the_axis_cancels_then_loads_itself(trio):
    """A new end behind the axis needs a reversal: the MTYPE move is cancelled at DECEL and
    the MOVEMODIFY then runs as a move of its own (MTYPE 5) to the position (spec §10.2)."""
    trio.move(0, "MOVE", [100])
    run_to(trio, 0.0505)  # at 45 units
    trio.move(0, "MOVEMODIFY", [10])
    run_to(trio, 1.0)
    assert [f["mtype"] for _, f in fields(trio, "move_start", axis=0)] == [1, 5]
    assert trio.axis(0)["dpos"] == pytest.approx(10.0)


def test_movemodify_on_an_idle_axis_is_an_absolute_move(trio):
    trio.terminal("MOVEMODIFY(50) AXIS(4)")
    run_to(trio, 0.0015)
    assert trio.axis(4)["mtype"] == 5
    run_to(trio, 1.0)
    assert trio.axis(4)["dpos"] == pytest.approx(50.0)


def test_movemodify_rewrites_the_move_waiting_in_ntype(trio):
    trio.move(0, "MOVE", [10])
    next_period(trio)
    trio.move(0, "MOVE", [10])  # NTYPE: would end at 20
    next_period(trio)
    trio.move(0, "MOVEMODIFY", [50])
    run_to(trio, 1.0)
    assert [f["mtype"] for _, f in fields(trio, "move_start", axis=0)] == [1, 1]
    assert trio.axis(0)["dpos"] == pytest.approx(50.0)


# -- DEFPOS / OFFPOS -------------------------------------------------------------------------


def test_defpos_takes_effect_at_the_next_servo_period(trio):
    """TRM (MC216 listing p. 220): DEFPOS takes effect at the next servo update; until then
    OFFPOS reads the pending shift, so ``WAIT UNTIL OFFPOS=0`` waits for it."""
    _program(trio, "DEFPOS(100) AXIS(0)\nVR(1)=DPOS AXIS(0)\nVR(2)=OFFPOS AXIS(0)\n"
                   "WAIT UNTIL OFFPOS AXIS(0)=0\nVR(3)=DPOS AXIS(0)\n")
    run_to(trio, 0.01)
    assert [trio.get_variable(f"VR({i})") for i in (1, 2, 3)] == [0.0, 100.0, 100.0]
    assert fields(trio, "offpos") == [(0.001, {"axis": 0, "offset": 100.0})]


def test_defpos_during_a_move_shifts_the_path_not_the_axis(trio):
    trio.move(0, "MOVE", [100])
    run_to(trio, 0.0505)
    at = trio.axis(0)["dpos"]
    trio.terminal("DEFPOS(0) AXIS(0)")
    run_to(trio, 0.0515)
    # at period 51 (one more unit at 1000 units/s) the position is declared 0
    assert trio.axis(0)["dpos"] == pytest.approx(0.0)
    assert trio.axis(0)["endmove"] == pytest.approx(100.0 - (at + 1.0))
    run_to(trio, 1.0)
    assert trio.axis(0)["dpos"] == pytest.approx(100.0 - (at + 1.0))


def test_offpos_write_shifts_by_the_value_at_the_next_servo_period(trio):
    trio.terminal("OFFPOS AXIS(2)=-5")
    assert trio.terminal("? OFFPOS AXIS(2)").reply == "-5.0000"
    run_to(trio, 0.0015)
    assert trio.axis(2)["dpos"] == -5.0
    assert trio.terminal("? OFFPOS AXIS(2)").reply == "0.0000"


# -- CANCEL with an S-ramp --------------------------------------------------------------------


@pytest.mark.parametrize(("sramp_ms", "ramp_periods"), [(0, 10), (10, 20)])
def test_cancel_ramps_down_with_the_axis_sramp(sramp_ms, ramp_periods):
    """CANCEL decelerates at DECEL; with SRAMP the ramp is S-shaped and SRAMP longer (1000
    units/s at 100 000: 10 ms, 20 ms with SRAMP 10 ms); half-way down the speed is half."""
    c = make()
    c.set_axis(0, sramp=sramp_ms)
    c.terminal("FORWARD AXIS(0)")
    run_to(c, 0.1005)
    c.terminal("CANCEL AXIS(0)")
    run_to(c, 0.1005 + ramp_periods / 2000)
    assert c.axis(0)["vp_speed"] == pytest.approx(500.0)
    run_to(c, 0.3)
    (end,) = [cycle(c, t) for t, _ in fields(c, "move_end", axis=0)]
    assert end == 100 + ramp_periods
    assert c.axis(0)["vp_speed"] == 0.0
