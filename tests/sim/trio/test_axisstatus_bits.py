"""AXISSTATUS: the bits the simulation knows (spec trio.md §1.6: bit 9 FS limit, 10 RS
limit, 11 move cancelling; bit 6 datuming ``[BK]``; sim/trio/card/axis_status.py). A move that
reaches a limit ramps down beyond it and is cancelled (tests/sim/trio/test_soft_limits.py); the
bit stays set while the axis is in the limit."""

from __future__ import annotations

from tests.sim.trio.conftest import make, run_to


def status(c, axis: int = 0) -> int:
    return int(float(c.terminal(f"? AXISSTATUS AXIS({axis})").reply))


def test_forward_software_limit_bit_set_at_and_beyond_fs_limit():
    c = make()
    c.terminal("FS_LIMIT=50")
    c.terminal("MOVE(100)")
    run_to(c, 0.03)
    assert c.axis(0)["dpos"] < 50 and status(c) & 512 == 0
    run_to(c, 0.5)
    assert c.axis(0)["dpos"] == 55.0  # stopped: ramped down past the limit (M216-367)
    assert status(c) == 512
    c.terminal("FS_LIMIT=55")
    assert status(c) == 512  # DPOS = FS_LIMIT counts as in the limit [INF]
    c.terminal("FS_LIMIT=55.5")
    assert status(c) == 0


def test_reverse_software_limit_bit_set_below_rs_limit():
    c = make()
    c.terminal("RS_LIMIT AXIS(1)=-20")
    c.terminal("MOVE(-30) AXIS(1)")
    run_to(c, 0.5)
    assert c.axis(1)["dpos"] == -25.0 and status(c, 1) == 1024
    assert status(c, 0) == 0  # the limit is axis 1's
    c.terminal("RS_LIMIT AXIS(1)=-25")
    assert status(c, 1) == 1024  # DPOS = RS_LIMIT counts as in the limit [INF]
    c.terminal("RS_LIMIT AXIS(1)=-25.5")
    assert status(c, 1) == 0


def test_move_cancelling_bit_while_a_cancelled_move_decelerates():
    c = make(decel=1000.0)  # one second to stop from SPEED 1000
    c.terminal("FORWARD")
    run_to(c, 0.1)
    assert status(c) == 0
    c.terminal("CANCEL")
    run_to(c, 0.2)
    assert c.axis(0)["mtype"] == 10 and status(c) == 2048
    run_to(c, 2.0)
    assert c.axis(0)["mtype"] == 0 and status(c) == 0


def test_datuming_bit_while_a_datum_move_executes():
    c = make()
    c.terminal("MOVE(50)")
    run_to(c, 0.2)
    c.terminal("DATUM_IN=5")
    c.set_variable("IN(5)", 1)  # the (active-low) datum switch is clear
    c.terminal("DATUM(4)")  # reverse at SPEED until the switch is reached
    run_to(c, 1.0)
    assert c.axis(0)["mtype"] == 12
    assert status(c) == 64
    c.set_variable("IN(5)", 0)  # reached: creep forward off it
    run_to(c, 1.5)
    c.set_variable("IN(5)", 1)
    run_to(c, 10.0)
    assert c.axis(0)["mtype"] == 0 and status(c) == 0


def test_no_datuming_bit_while_a_linked_move_executes():
    c = make()
    c.terminal("CONNECT(1,1) AXIS(0)")
    run_to(c, 0.01)
    assert c.axis(0)["mtype"] == 21
    assert status(c) == 0


def test_motion_error_stays_zero_with_a_limit_bit_in_errormask():
    c = make()
    c.terminal("ERRORMASK=512")
    c.terminal("FS_LIMIT=5")
    c.terminal("MOVE(10)")
    run_to(c, 0.5)
    assert status(c) == 512
    # no error model: the real controller would raise MOTION_ERROR and drop WDOG
    assert c.terminal("? MOTION_ERROR").reply == "0.0000"
