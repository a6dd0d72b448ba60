"""Issue 22 item 6: what read wrong before, each against the manual paragraph it breaks.

* TJ1P-27 (spec §9.2): MPOS / DPOS are integer edge counters; a fraction of an encoder edge
  above 0.9 is rounded up, otherwise down — on every move.
* TRM p. 8-30 (MC216 listing p. 220): DEFPOS and OFFPOS both act at the next servo update,
  DEFPOS as an OFFPOS; neither is lost when both are written in one servo period.
* MERGE (spec §11.10 ``[BK]``): with MERGE ON the axis does not stop between consecutive
  moves, so VP_SPEED, MSPEED and MTYPE do not read a stop at the joint.
"""

from __future__ import annotations

import pytest

from tests.sim.trio.conftest import cycle, fields, make, next_period, run_to

# -- whole encoder edges ---------------------------------------------------------------------


@pytest.mark.parametrize(("distance", "dpos"), [
    (0.00095, 0.001),  # 0.95 edge: above 0.9, rounded up
    (0.0009, 0.0),  # 0.9 edge: not above 0.9, rounded down
    (0.0005, 0.0),  # half an edge: down
    (0.0125, 0.012),  # 12.5 edges -> 12
    (-0.00095, -0.001),  # the same magnitude rule backwards
    (2.00096, 2.001),
])
def test_tj1p27_a_fraction_of_an_edge_above_0_9_rounds_up_otherwise_down(distance, dpos):
    c = make(units=1000)
    assert c.terminal(f"MOVE({distance})").error is None
    run_to(c, 1.0)
    assert c.axis(0)["dpos"] == pytest.approx(dpos, abs=1e-12)
    assert c.axis(0)["dpos"] * 1000 == pytest.approx(round(dpos * 1000), abs=1e-9)


def test_tj1p27_the_rounding_holds_on_every_move_so_fractions_do_not_accumulate():
    """Ten MOVE(0.0005) at UNITS 1000: each is half an edge and rounds down, so the axis
    never moves (a float position would have reached 0.005)."""
    c = make(units=1000)
    c.store_program("CREEPER", "FOR i=1 TO 10\n  MOVE(0.0005)\n  WAIT IDLE\nNEXT i\n"
                    "VR(0)=DPOS*1000\n")
    c.run_program("CREEPER", 1)
    run_to(c, 2.0)
    assert c.get_variable("VR(0)") == 0.0


def test_tj1p27_moveabs_and_interpolated_moves_end_on_whole_edges():
    c = make(units=1000)
    c.terminal("MOVEABS(1.23456)")
    run_to(c, 1.0)
    assert c.axis(0)["dpos"] == pytest.approx(1.234, abs=1e-12)  # 1234.56 edges: 0.56 down
    c.terminal("MOVE(0.00099,0.00091) AXIS(0)")
    run_to(c, 2.0)
    assert c.axis(0)["dpos"] == pytest.approx(1.235, abs=1e-12)  # 0.99 and 0.91 edge: up
    assert c.axis(1)["dpos"] == pytest.approx(0.001, abs=1e-12)


# -- OFFPOS in the servo period of a DEFPOS --------------------------------------------------


def test_trm_p8_30_offpos_after_defpos_in_one_servo_period_is_not_dropped():
    c = make()
    c.terminal("MOVE(10)")
    run_to(c, 0.5)
    c.terminal("DEFPOS(100)")
    c.terminal("OFFPOS=5")
    assert c.terminal("? OFFPOS").reply == "95.0000"  # the shift pending: to 100, then +5
    run_to(c, 0.5015)
    assert c.axis(0)["dpos"] == 105.0
    assert c.terminal("? OFFPOS").reply == "0.0000"
    assert [f["offset"] for _t, f in fields(c, "offpos", axis=0)] == [95.0]


def test_trm_p8_30_defpos_after_offpos_in_one_period_sets_the_position():
    c = make()
    c.store_program("P", "OFFPOS=5\nDEFPOS(-20)\nWAIT UNTIL OFFPOS=0\nVR(0)=DPOS\n"
                    "OFFPOS=2\nOFFPOS=3\nWAIT UNTIL OFFPOS=0\nVR(1)=DPOS\n")
    c.run_program("P", 1)
    run_to(c, 0.1)
    assert (c.get_variable("VR(0)"), c.get_variable("VR(1)")) == (-20.0, -15.0)


# -- the MERGE joint ----------------------------------------------------------------------------


def test_merge_joint_mtype_vp_speed_and_mspeed_never_read_a_stop():
    """Two merged MOVE(100) at 1000 units/s: at every servo period from the first move's
    start to the second's ramp down MTYPE reads 1 and VP_SPEED / MSPEED read SPEED once
    cruising — the joint (period 106) included."""
    c = make()
    c.set_axis(0, merge=1)
    c.move(0, "MOVE", [100])
    next_period(c)
    c.move(0, "MOVE", [100])
    seen = []
    for k in range(11, 200):
        run_to(c, (k + 0.5) * c.clock.period_s)
        seen.append((k, c.terminal("? MTYPE").reply, c.terminal("? VP_SPEED").reply,
                     c.terminal("? MSPEED").reply))
    assert all(r == (k, "1.0000", "1000.0000", "1000.0000") for r, k in
               zip(seen, range(11, 200), strict=True)), [r for r in seen if r[1] != "1.0000"]
    (e1,) = [cycle(c, t) for t, _ in fields(c, "move_end", axis=0)][:1]
    starts = [cycle(c, t) for t, _ in fields(c, "move_start", axis=0)]
    assert starts[1] == e1 == 106
