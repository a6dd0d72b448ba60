"""Documented effects of the start-up parameters: ADDAX (M216-203, TRM p. 8-13), REP_DIST /
REP_OPTION (TKB-REP), CLUTCH_RATE on CONNECT (TJ2P-71), in virtual time."""

from __future__ import annotations

import pytest

from tests.sim.trio.conftest import fields, make, run_to


def test_m216_203_addax_sums_demand_changes_in_encoder_edges():
    """The manual's example: base axis UNITS 1000, added axis UNITS 20; MOVE(1) on the base
    and MOVE(2) on the added axis give 1000 + 2 x 20 = 1040 edges on the base axis."""
    c = make()
    c.set_axis(0, units=1000)
    c.set_axis(1, units=20)
    assert c.terminal("ADDAX(1) AXIS(0)").error is None
    c.terminal("MOVE(1) AXIS(0)")
    c.terminal("MOVE(2) AXIS(1)")
    run_to(c, 1.0)
    assert c.axis(0)["dpos"] * 1000 == pytest.approx(1040.0)
    assert c.axis(1)["dpos"] == 2.0
    assert [f["command"] for _t, f in fields(c, "setup", axis=0)] == ["ADDAX"]


def test_m216_203_addax_minus_1_ends_the_link_and_keeps_what_was_added():
    c = make()
    c.terminal("ADDAX(1) AXIS(0)")
    c.terminal("MOVE(5) AXIS(1)")
    run_to(c, 0.5)
    c.terminal("ADDAX(-1) AXIS(0)")
    c.terminal("MOVE(7) AXIS(1)")
    run_to(c, 1.0)
    assert (c.axis(0)["dpos"], c.axis(1)["dpos"]) == (5.0, 12.0)


def test_m216_203_addax_follows_the_added_axis_while_it_moves():
    c = make()
    c.terminal("ADDAX(2) AXIS(0)")
    c.terminal("MOVE(100) AXIS(2)")
    run_to(c, 0.0505)
    assert c.axis(0)["dpos"] == pytest.approx(c.axis(2)["dpos"])
    assert c.axis(0)["mtype"] == 0  # no move of its own


def test_addax_onto_itself_through_a_chain_is_an_error():
    c = make()
    c.terminal("ADDAX(1) AXIS(0)")
    r = c.terminal("ADDAX(0) AXIS(1)")
    assert r.error is not None and "ADDAX" in r.error


@pytest.mark.parametrize(("option", "distance", "dpos"), [
    (0, 400.0, -320.0),  # range -360..+360: past +360 it reads from -360 on
    (1, 400.0, 40.0),  # range 0..360
    (1, -30.0, 330.0),
    (0, 100.0, 100.0),
])
def test_tkb_rep_dist_wraps_dpos_and_mpos(option, distance, dpos):
    c = make()
    c.terminal("REP_DIST=360")
    c.terminal(f"REP_OPTION={option}")
    c.terminal(f"MOVE({distance})")
    run_to(c, 2.0)
    assert c.axis(0)["dpos"] == pytest.approx(dpos)
    assert c.terminal("? MPOS").reply == f"{dpos:.4f}"


def test_tkb_rep_dist_moveabs_goes_to_its_target_within_the_range():
    c = make()
    c.terminal("REP_DIST=360")
    c.terminal("REP_OPTION=1")
    c.terminal("MOVE(400)")
    run_to(c, 1.0)
    c.terminal("MOVEABS(90)")  # from 40: +50
    run_to(c, 2.0)
    assert c.axis(0)["dpos"] == 90.0


def test_tj2p71_clutch_rate_ramps_the_connect_ratio():
    """CLUTCH_RATE 10 (ratio per second): CONNECT(2,1) reaches its ratio after 0.2 s; the
    master at 1000 units/s is geared up linearly meanwhile, so the slave has moved
    about 1000 x 2 x 0.2 / 2 = 200 units when the ratio is reached, then 2000 units/s."""
    c = make()
    c.terminal("FORWARD AXIS(1)")
    run_to(c, 0.1005)  # the master at speed
    c.terminal("CLUTCH_RATE AXIS(0)=10")
    c.terminal("CONNECT(2,1) AXIS(0)")
    run_to(c, 0.1025)
    start = c.axis(0)["dpos"]
    assert start == pytest.approx(0.0, abs=0.05)
    run_to(c, 0.2025)  # half way up the ramp: ratio 1
    mid = c.axis(0)["dpos"]
    assert mid == pytest.approx(50.0, abs=2.0)
    run_to(c, 0.3025)
    up = c.axis(0)["dpos"]
    assert up == pytest.approx(200.0, abs=3.0)
    run_to(c, 0.4025)
    assert c.axis(0)["dpos"] - up == pytest.approx(200.0, abs=0.01)  # ratio 2 from now on


def test_clutch_rate_0_connects_at_once():
    c = make()
    c.terminal("FORWARD AXIS(1)")
    run_to(c, 0.1005)
    c.terminal("CONNECT(2,1) AXIS(0)")
    run_to(c, 0.1025)
    a = c.axis(0)["dpos"]
    run_to(c, 0.2025)
    assert c.axis(0)["dpos"] - a == pytest.approx(200.0)
