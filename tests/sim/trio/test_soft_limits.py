"""Software limits stop motion (TRM, MC216 listing p. 8-177, RS_LIMIT / FS_LIMIT: "When the
limit is hit the controller will ramp down the speed to zero then cancel the move. Bit 10 in
the axis status parameter is set when the axis is in the RS_LIMIT"; bit 9 FS_LIMIT, spec §1.6).

Axis settings of conftest: SPEED 1000, ACCEL = DECEL = 100 000 (a ramp of 0.01 s over 5 units).
"""

from __future__ import annotations

import pytest

from tests.sim.trio.conftest import fields, make, run_to


def status(c, axis: int = 0) -> int:
    return int(float(c.terminal(f"? AXISSTATUS AXIS({axis})").reply))


def limit_events(c) -> list[tuple[float, int, str]]:
    return [(round(t, 6), f["axis"], f["limit"]) for t, f in fields(c, "soft_limit")]


def test_move_through_fs_limit_ramps_down_at_decel_and_is_cancelled():
    c = make()
    c.terminal("FS_LIMIT=50")
    c.terminal("MOVE(100)")
    c.terminal("MOVE(-20)")  # waits in NTYPE: loads once the limit has cancelled the first
    run_to(c, 0.03)
    assert status(c) == 0
    run_to(c, 0.06)
    # starts at 1 ms, 5 units of ramp up to 11 ms, then 1000 units/s: DPOS = 50 at 56 ms
    assert limit_events(c) == [(0.056, 0, "FS_LIMIT")]
    assert c.axis(0)["mtype"] == 1 and status(c) == 512 | 2048  # in the limit, cancelling
    run_to(c, 0.0665)
    # ramped down at DECEL from 1000: 1000² / (2 x 100 000) = 5 units beyond the limit
    assert c.axis(0)["dpos"] == 55.0
    ends = [(round(t, 6), f["mtype"]) for t, f in fields(c, "move_end")]
    assert ends == [(0.066, 1)]  # cancelled at the end of the ramp, not at 100
    run_to(c, 0.5)
    assert c.axis(0)["dpos"] == 35.0  # the buffered MOVE(-20) ran: the way back is free
    assert status(c) == 0


def test_decel_sets_the_overrun_and_fastdec_replaces_it():
    """The ramp is DECEL's (TRM p. 8-177); FASTDEC, when set, is used instead [BK]."""
    slow = make(decel=10_000.0)
    slow.terminal("FS_LIMIT=50")
    slow.terminal("MOVE(200)")
    run_to(slow, 1.0)
    assert slow.axis(0)["dpos"] == 100.0  # 1000² / (2 x 10 000) = 50 beyond
    fast = make(decel=10_000.0)
    fast.terminal("FS_LIMIT=50")
    fast.terminal("FASTDEC=500000")
    fast.terminal("MOVE(200)")
    run_to(fast, 1.0)
    assert fast.axis(0)["dpos"] == 51.0  # 1000² / (2 x 500 000) = 1 beyond


def test_reverse_runs_into_rs_limit():
    c = make(decel=1000.0)
    c.terminal("RS_LIMIT=-100")
    c.terminal("REVERSE")
    run_to(c, 0.5)
    # 5 units of ramp by 11 ms, then -1000/s: -100 at 106 ms; one second to stop
    assert limit_events(c) == [(0.106, 0, "RS_LIMIT")]
    assert c.axis(0)["mtype"] == 11 and status(c) == 1024 | 2048
    run_to(c, 3.0)
    assert c.axis(0)["mtype"] == 0 and c.axis(0)["dpos"] == -600.0
    assert status(c) == 1024


def test_forward_and_moveabs_stop_at_fs_limit_too():
    c = make()
    c.terminal("FS_LIMIT=30")
    c.terminal("FORWARD")
    run_to(c, 1.0)
    assert limit_events(c) == [(0.036, 0, "FS_LIMIT")] and c.axis(0)["dpos"] == 35.0
    d = make()
    d.terminal("FS_LIMIT=30")
    d.terminal("MOVEABS(80)")
    run_to(d, 1.0)
    assert limit_events(d) == [(0.036, 0, "FS_LIMIT")] and d.axis(0)["dpos"] == 35.0


def test_a_move_ending_exactly_on_the_limit_is_not_cancelled():
    c = make()
    c.terminal("FS_LIMIT=50")
    c.terminal("MOVE(50)")
    run_to(c, 1.0)
    assert limit_events(c) == [] and c.axis(0)["dpos"] == 50.0
    assert status(c) == 512  # DPOS = FS_LIMIT reads as in the limit [INF]


def test_beyond_the_limit_a_move_outwards_is_cancelled_and_one_inwards_runs():
    c = make()
    c.terminal("FS_LIMIT=50")
    c.terminal("MOVE(100)")
    run_to(c, 1.0)
    assert c.axis(0)["dpos"] == 55.0
    c.terminal("MOVE(10)")
    run_to(c, 1.1)
    assert c.axis(0)["dpos"] == 55.0  # cancelled in its first servo period
    assert [(round(t, 6), f["limit"]) for t, f in fields(c, "soft_limit")][-1] == (
        1.001, "FS_LIMIT")
    c.terminal("MOVE(-10)")
    run_to(c, 1.2)
    assert c.axis(0)["dpos"] == 45.0 and len(limit_events(c)) == 2


def test_an_interpolated_move_stops_on_the_limit_of_any_of_its_axes():
    """BASE(0,1) MOVE: the axis 1 limit cancels the whole vector move, both axes ramp."""
    c = make()
    c.terminal("RS_LIMIT AXIS(1)=-30")
    c.terminal("BASE(0,1)")
    c.terminal("MOVE(300,-400)")  # path 500, axis 1 at -0.8 of the path speed
    run_to(c, 1.0)
    assert [e[1:] for e in limit_events(c)] == [(1, "RS_LIMIT")]
    x, y = c.axis(0)["dpos"], c.axis(1)["dpos"]
    # 5 path units of ramp down after the hit: 3 more on axis 0, 4 more on axis 1
    assert y == pytest.approx(-30.0 - 4.0, abs=0.81) and y < -30.0
    assert abs(x + 0.75 * y) <= 1.0  # the 3:4 path, each axis at rest on a whole edge
    assert c.axis(0)["mtype"] == 0 and c.axis(1)["mtype"] == 0


def test_movecirc_is_stopped_where_its_arc_crosses_the_limit():
    """A half circle of radius 50 about (50, 0) from (0, 0): axis 1 rises to 50 at the top."""
    c = make()
    c.terminal("FS_LIMIT AXIS(1)=20")
    c.terminal("BASE(0,1)")
    c.terminal("MOVECIRC(100,0,50,0,1)")
    run_to(c, 1.0)
    assert [e[1:] for e in limit_events(c)] == [(1, "FS_LIMIT")]
    y = c.axis(1)["dpos"]
    assert 20.0 < y < 26.0  # within the 5 path units of the ramp past the limit
    assert c.axis(0)["mtype"] == 0


def test_a_linked_move_is_stopped_at_the_limit():
    """CONNECT follows axis 1; at the limit it stops where it is (a linked move, as on
    CANCEL)."""
    c = make()
    c.terminal("FS_LIMIT=40")
    c.terminal("CONNECT(2,1)")
    c.terminal("MOVE(100) AXIS(1)")
    run_to(c, 1.0)
    assert [e[1:] for e in limit_events(c)] == [(0, "FS_LIMIT")]
    assert 40.0 <= c.axis(0)["dpos"] <= 42.0  # one servo period of 2 x 1000 units/s past
    assert c.axis(0)["mtype"] == 0
    assert c.axis(1)["dpos"] == 100.0  # the link axis runs on


def test_limits_written_while_a_move_runs_take_effect():
    c = make()
    c.terminal("MOVE(100)")
    run_to(c, 0.03)
    c.terminal("FS_LIMIT=40")
    run_to(c, 1.0)
    assert limit_events(c) == [(0.046, 0, "FS_LIMIT")] and c.axis(0)["dpos"] == 45.0


def test_a_program_sees_the_limit_in_axisstatus_and_the_move_gone():
    c = make(model="mc4xx")
    c.store_program("LIM", "FS_LIMIT=50\nMOVE(100)\nWAIT IDLE\nVR(1)=AXISSTATUS\n"
                   "VR(2)=DPOS\nVR(3)=AXISSTATUS.9\n")
    c.run_program("LIM")
    run_to(c, 1.0)
    assert [c.get_variable(f"VR({n})") for n in (1, 2, 3)] == [512.0, 55.0, 1.0]


@pytest.mark.parametrize(
    ("setup", "command", "axis", "which"),
    [
        ((), "MOVESP(100)", 0, "FS_LIMIT"),  # an SP move at FORCE_SPEED
        (("BASE(0,1,2)",), "MHELICAL(0,0,10,0,0,100)", 2, "FS_LIMIT"),  # the helix' 3rd axis
        ((), "MOVELINK(100,100,0,0,1)", 0, "FS_LIMIT"),  # linked to axis 1
        (("TABLE(0,0,50,100)",), "CAMBOX(0,2,1,100,1)", 0, "FS_LIMIT"),
        (("BASE(0,1)",), "MOVECIRC(0,0,-50,0,0)", 0, "RS_LIMIT"),  # a full circle, x to -100
    ],
)
def test_every_move_type_that_moves_the_axis_stops_at_its_limit(setup, command, axis, which):
    c = make()
    c.terminal("FS_LIMIT AXIS(0)=40")
    c.terminal("FS_LIMIT AXIS(2)=40")
    c.terminal("RS_LIMIT AXIS(0)=-40")
    for line in setup:
        assert c.terminal(line).error is None, line
    assert c.terminal(command).error is None
    if "LINK" in command or "CAMBOX" in command:
        c.terminal("MOVE(200) AXIS(1)")  # the link axis drives the move
    run_to(c, 2.0)
    assert [e[1:] for e in limit_events(c)] == [(axis, which)]
    pos = c.axis(axis)["dpos"]
    assert (40.0 <= pos <= 46.0) if which == "FS_LIMIT" else (-46.0 <= pos <= -40.0)
    assert c.axis(axis)["mtype"] == 0


def test_movemodify_to_beyond_the_limit_is_stopped_there():
    c = make()
    c.terminal("FS_LIMIT=60")
    c.terminal("MOVE(50)")
    c.terminal("MOVEMODIFY(200)")
    run_to(c, 1.0)
    assert limit_events(c) == [(0.066, 0, "FS_LIMIT")] and c.axis(0)["dpos"] == 65.0
