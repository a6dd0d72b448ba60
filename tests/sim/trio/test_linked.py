"""CONNECT, CAM, CAMBOX and MOVELINK: moves linked to another axis or to the TABLE.

Sources (spec §10.3): CONNECT TJ2P-71 and the Trio KB (ratio in encoder edges, UNITS not
applied, ended by CANCEL); CAM TRM p. 8-17 (MC206 listing p. 207: table values are absolute
positions from the start in encoder edges times the multiplier; the time taken is the distance
at SPEED, ramped at ACCEL); CAMBOX TRM p. 8-19 (MC206 listing p. 209: the same table driven
by the link axis' measured motion over the link distance); MOVELINK help text (ratio ramps over
link_acc / link_dec). Axis settings (conftest): SPEED 1000, ACCEL = DECEL = 100 000.
"""

from __future__ import annotations

import pytest

from tests.sim.trio.conftest import cycle, fields, run_to


def _run(c, text: str) -> None:
    c.store_program("L", text)
    c.run_program("L", 1)


def test_connect_follows_the_driving_axis_in_encoder_edges(trio):
    """CONNECT(0.5, 0) on axis 1 with UNITS 10 on axis 0: 100 units of axis 0 are 1000 edges,
    so axis 1 (UNITS 1) moves 500 — the ratio ignores UNITS (Trio KB)."""
    trio.set_axis(0, units=10)
    _run(trio, "CONNECT(0.5,0) AXIS(1)\nWA(5)\nMOVE(100) AXIS(0)\nWAIT IDLE AXIS(0)\n"
               "VR(1)=MTYPE AXIS(1)\nVR(2)=DPOS AXIS(1)\nCANCEL AXIS(1)\nWAIT IDLE AXIS(1)\n"
               "VR(3)=MTYPE AXIS(1)\n")
    run_to(trio, 0.005)  # CONNECT loaded at period 1; axis 0 starts after WA(5)
    assert trio.axis(1)["mtype"] == 21 and trio.axis(1)["dpos"] == 0.0
    run_to(trio, 0.05)
    assert trio.axis(1)["dpos"] == pytest.approx(5.0 * trio.axis(0)["dpos"])
    run_to(trio, 1.0)
    assert [trio.get_variable(f"VR({i})") for i in (1, 2, 3)] == pytest.approx([21, 500, 0])
    assert [f["mtype"] for _, f in fields(trio, "move_end", axis=1)] == [21]


def test_connect_never_ends_by_itself(trio):
    trio.terminal("CONNECT(2,3) AXIS(0)")
    trio.terminal("FORWARD AXIS(3)")
    run_to(trio, 2.0)
    assert trio.axis(0)["mtype"] == 21
    assert trio.axis(0)["dpos"] == pytest.approx(2.0 * trio.axis(3)["dpos"])


def test_a_new_connect_changes_the_ratio_without_a_step(trio):
    """TJ2P-71: CONNECT again on the same axis changes the ratio at any time."""
    trio.terminal("CONNECT(1,0) AXIS(1)")
    run_to(trio, 0.0015)
    trio.terminal("FORWARD AXIS(0)")
    run_to(trio, 0.1005)
    a0, a1 = trio.axis(0)["dpos"], trio.axis(1)["dpos"]
    assert a1 == pytest.approx(a0)
    trio.terminal("CONNECT(3,0) AXIS(1)")
    run_to(trio, 0.1015)  # transferred at period 101: from here 3 x what axis 0 moves
    b0, b1 = trio.axis(0)["dpos"], trio.axis(1)["dpos"]
    assert b1 == pytest.approx(a1 + (b0 - a0))  # no step: the old ratio up to period 101
    run_to(trio, 0.2005)
    assert trio.axis(1)["dpos"] - b1 == pytest.approx(3.0 * (trio.axis(0)["dpos"] - b0))
    assert len(fields(trio, "move_start", axis=1)) == 1  # still the first CONNECT in MTYPE


def test_cam_follows_the_table_over_distance_at_speed(trio):
    """CAM(0, 2, 1, 100): 100 units at SPEED 1000 with 10 ms ramps take 110 periods; half-way
    (50 of 100) it is at table point 1; ENDMOVE is the previous end during the cam."""
    trio.set_variable("TABLE(0)", 0)
    trio.set_variable("TABLE(1)", 100)
    trio.set_variable("TABLE(2)", 400)
    trio.terminal("CAM(0,2,1,100) AXIS(2)")
    run_to(trio, 0.0015)
    assert (trio.axis(2)["mtype"], trio.axis(2)["endmove"]) == (13, 0.0)
    run_to(trio, 0.0565)  # 55 periods in: 50 units of the distance
    assert trio.axis(2)["dpos"] == pytest.approx(100.0)
    run_to(trio, 0.5)
    ((start, _),) = fields(trio, "move_start", axis=2)
    ((end, _),) = fields(trio, "move_end", axis=2)
    assert (cycle(trio, start), cycle(trio, end)) == (1, 111)
    assert trio.axis(2)["dpos"] == pytest.approx(400.0)


def test_cam_multiplier_scales_and_speed_changes_its_rate(trio):
    trio.terminal("TABLE(0,0,50,100)")
    trio.terminal("CAM(0,2,2,100) AXIS(0)")
    run_to(trio, 0.0205)
    trio.set_axis(0, speed=500)  # half the rate from here on
    run_to(trio, 1.0)
    ((end, _),) = fields(trio, "move_end", axis=0)
    assert cycle(trio, end) > 150
    assert trio.axis(0)["dpos"] == pytest.approx(200.0)


def test_cambox_runs_over_the_link_distance_of_the_link_axis(trio):
    """CAMBOX(10, 12, 1, 200, 0) on axis 1: half-way along axis 0's 200 units it is at table
    point 11; it ends in the servo period where axis 0 has moved 200, while axis 0 goes on."""
    trio.terminal("TABLE(10,0,50,100)")
    trio.terminal("CAMBOX(10,12,1,200,0) AXIS(1)")
    run_to(trio, 0.0015)
    trio.terminal("MOVE(400) AXIS(0)")  # starts at period 2: 200 units by period 2 + 205
    run_to(trio, 0.1075)  # axis 0 at 100 (5 units ramping, then 95 at 1000 units/s)
    assert trio.axis(0)["dpos"] == pytest.approx(100.0)
    assert trio.axis(1)["dpos"] == pytest.approx(50.0)
    assert trio.axis(1)["remain"] == pytest.approx(100.0)
    run_to(trio, 1.0)
    ((end, f),) = fields(trio, "move_end", axis=1)
    assert (cycle(trio, end), f["mtype"]) == (207, 20)
    assert trio.axis(1)["dpos"] == pytest.approx(100.0)
    assert trio.axis(0)["dpos"] == pytest.approx(400.0)


def test_movelink_ramps_its_ratio_over_link_acc_and_link_dec(trio):
    """MOVELINK(100, 200, 50, 50, 0): ratio 100 / (200 - 50) = 2/3 at constant speed; over
    the first 50 of the link distance the ratio ramps up (25 -> 25²/100 x 2/3 = 4.1667)."""
    trio.terminal("MOVELINK(100,200,50,50,0) AXIS(1)")
    run_to(trio, 0.0015)
    trio.terminal("MOVE(400) AXIS(0)")
    run_to(trio, 0.0325)  # axis 0 at 25
    assert trio.axis(0)["dpos"] == pytest.approx(25.0)
    assert trio.axis(1)["dpos"] == pytest.approx(25.0 * 25.0 / 100.0 * 2.0 / 3.0)
    run_to(trio, 0.1075)  # axis 0 at 100: half of the move (symmetric ramps)
    assert trio.axis(1)["dpos"] == pytest.approx(50.0)
    run_to(trio, 1.0)
    ((end, f),) = fields(trio, "move_end", axis=1)
    assert (cycle(trio, end), f["mtype"]) == (207, 22)
    assert trio.axis(1)["dpos"] == pytest.approx(100.0)


def test_cancel_stops_a_linked_move_where_it_is(trio):
    trio.terminal("CONNECT(1,0) AXIS(1)")
    run_to(trio, 0.0015)
    trio.terminal("FORWARD AXIS(0)")
    run_to(trio, 0.1005)
    at = trio.axis(1)["dpos"]
    trio.terminal("CANCEL AXIS(1)")
    run_to(trio, 0.3)
    assert trio.axis(1)["mtype"] == 0 and trio.axis(1)["dpos"] == pytest.approx(at)


@pytest.mark.parametrize(
    ("line", "message"),
    [
        ("CONNECT(1,0) AXIS(0)", "link axis must not be the base axis"),
        ("CAMBOX(0,1,1,100,3,1) AXIS(0)", "link_options bit 0 not simulated"),
        ("CAM(5,5,1,100) AXIS(0)", "TABLE points 5..5 out of range"),
        ("MOVELINK(10,0,0,0,3) AXIS(0)", "link distance must be positive"),
    ],
)
def test_bad_linked_commands_are_runtime_errors_that_change_nothing(trio, line, message):
    r = trio.terminal(line)
    assert r.error is not None and message in r.error
    assert trio.axis(0)["mtype"] == 0 and trio.pmove(0) == 0
