"""MOVELINK and CAMBOX in their MC4 forms: link_options, the 8-argument base-distance form,
pattern mode (MOVELINK-MD, CAMBOX-MD: the MC4 help text; spec §10.3, §11.9)."""

from __future__ import annotations

import pytest

from tests.sim.trio.conftest import cycle, fields, make, run_to


def _master(c, speed: float = 1000.0, axis: int = 1) -> None:
    c.set_axis(axis, speed=speed)
    c.terminal(f"FORWARD AXIS({axis})")


def test_movelink_md_example2_repeating_exact_gearbox_ends_at_a_cycle_end_on_rep_option():
    """MOVELINK(4000, 3072, 0, 0, link, 4): an exact 4000/3072 gearbox repeating until
    REP_OPTION bit 1 is set; then it ends at the end of the cycle under way and the firmware
    clears the bit again."""
    c = make()
    c.terminal("MOVELINK(4000,3072,0,0,1,4) AXIS(0)")
    run_to(c, 0.0025)
    _master(c, speed=100_000.0)
    run_to(c, 0.1005)
    m = c.axis(1)["dpos"]
    assert c.axis(0)["dpos"] == pytest.approx(m * 4000 / 3072, abs=0.5)
    assert c.axis(0)["mtype"] == 22
    c.terminal("REP_OPTION AXIS(0)=2")
    run_to(c, 0.4)  # the master passes 3072 (the end of the first cycle) at about 0.25 s
    assert c.axis(1)["dpos"] > 3072
    cycles = -(-m // 3072)  # the cycle under way when the bit was set
    assert c.axis(0)["mtype"] == 0
    assert c.axis(0)["dpos"] == pytest.approx(cycles * 4000)
    assert c.terminal("? REP_OPTION AXIS(0)").reply == "0.0000"


def test_movelink_md_option_2_starts_when_the_link_axis_reaches_link_pos():
    c = make()
    _master(c)
    c.terminal("MOVELINK(50,100,0,0,1,2,300) AXIS(0)")
    run_to(c, 0.25)  # master near 245: still waiting, MTYPE loaded
    assert c.axis(0)["mtype"] == 22 and c.axis(0)["dpos"] == 0.0
    run_to(c, 0.3505)
    assert c.axis(0)["dpos"] == pytest.approx((c.axis(1)["dpos"] - 300) / 2, abs=0.6)
    run_to(c, 0.5)
    assert c.axis(0)["dpos"] == 50.0 and c.axis(0)["mtype"] == 0


def test_movelink_md_option_32_link_only_while_the_link_axis_moves_positive():
    c = make()
    c.terminal("MOVELINK(100,100,0,0,1,32) AXIS(0)")
    run_to(c, 0.0025)
    c.terminal("MOVE(-30) AXIS(1)")  # backwards: no effect
    run_to(c, 0.2)
    assert c.axis(0)["dpos"] == 0.0
    c.terminal("MOVE(50) AXIS(1)")
    run_to(c, 0.4)
    assert c.axis(0)["dpos"] == pytest.approx(50.0)


def test_movelink_md_example5_base_distance_compound_profile_keeps_the_ratio_at_the_joints():
    """Three MOVELINKs (the 2nd with base_dist) merge into one profile: ratio 1 up to 250 of
    link travel, down to 1:3 over the next 90, 1:3 then down to rest: 200, 260, 370."""
    c = make()
    c.store_program("SHEAR", "MOVELINK(200,250,100,0,1,16)\nMOVELINK(60,90,0,90,1,16,0,30)\n"
                    "MOVELINK(110,360,0,60,1,16)\n")
    c.run_program("SHEAR", 2)
    run_to(c, 0.01)
    c.set_axis(1, speed=100.0)
    c.terminal("FORWARD AXIS(1)")
    ends = []
    run_to(c, 8.0)
    ends = [cycle(c, t) for t, _ in fields(c, "move_end", axis=0)]
    starts = [cycle(c, t) for t, _ in fields(c, "move_start", axis=0)]
    assert len(ends) == 3 and starts[1:] == ends[:2]  # no servo period without MTYPE 22
    assert c.axis(0)["dpos"] == 370.0


def _ratio_at(c, t: float, dt: float = 0.05) -> float:
    run_to(c, t)
    s0, m0 = c.axis(0)["dpos"], c.axis(1)["dpos"]
    run_to(c, t + dt)
    return (c.axis(0)["dpos"] - s0) / (c.axis(1)["dpos"] - m0)


def test_movelink_md_base_distance_starts_and_ends_at_the_base_ratio():
    """MOVELINK(60,90,0,90,link,0,0,30): base ratio 30/90 = 1/3 under a decel from 2/3 more:
    the slave starts at ratio 1 and ends at 1/3 (MOVELINK-MD example 5, second move)."""
    c = make()
    c.terminal("MOVELINK(60,90,0,90,1,0,0,30) AXIS(0)")
    run_to(c, 0.0025)
    c.set_axis(1, speed=100.0)
    c.terminal("FORWARD AXIS(1)")
    assert _ratio_at(c, 0.02, 0.02) == pytest.approx(1.0, abs=0.05)
    assert _ratio_at(c, 0.86, 0.02) == pytest.approx(1 / 3, abs=0.05)
    run_to(c, 1.5)
    assert c.axis(0)["dpos"] == 60.0


@pytest.mark.parametrize(("curve", "peak"), [(0, 1.55), (1, 2.42), (2, 2.16), (3, 1.86),
                                             (4, 1.0)])
def test_movelink_md_bit4_curved_ramps_peak_acceleration(curve, peak):
    """Bits 10..12 pick the curve; the help text gives each peak accel vs the linear ramp."""
    c = make(units=1000)
    opts = 16 + (curve << 10)
    c.terminal(f"MOVELINK(50,100,100,0,1,{opts}) AXIS(0)")
    run_to(c, 0.0025)
    c.set_axis(1, speed=100.0)
    c.terminal("FORWARD AXIS(1)")
    run_to(c, 1.2)
    assert c.axis(0)["dpos"] == 50.0
    # the slave speed ramps 0 -> 100 over 1 s; its largest change over 10 ms
    c2 = make(units=1000)
    c2.terminal(f"MOVELINK(50,100,100,0,1,{opts}) AXIS(0)")
    run_to(c2, 0.0025)
    c2.set_axis(1, speed=100.0, accel=1e9, decel=1e9)
    c2.terminal("FORWARD AXIS(1)")
    pos = []
    for k in range(0, 105):
        run_to(c2, 0.0055 + k * 0.01)
        pos.append(c2.axis(0)["dpos"])
    speeds = [(b - a) / 0.01 for a, b in zip(pos, pos[1:], strict=False)]
    accel = max((b - a) / 0.01 for a, b in zip(speeds, speeds[1:], strict=False))
    assert accel / 100.0 == pytest.approx(peak, rel=0.06)


@pytest.mark.parametrize(("options", "bit"), [(1, "0"), (256, "8"), (512, "9"), (16384, "14")])
def test_registration_start_options_are_refused_as_not_simulated(options, bit):
    c = make()
    r = c.terminal(f"MOVELINK(10,10,0,0,1,{options}) AXIS(0)")
    assert r.error is not None and f"bit {bit} not simulated" in r.error
    run_to(c, 0.01)
    assert c.axis(0)["mtype"] == 0


def test_cambox_md_example3_repeating_cam_ends_at_the_cycle_end_on_rep_option():
    c = make()
    c.terminal("TABLE(0,0,100,200,100,0)")  # a rise and return, encoder edges
    c.terminal("CAMBOX(0,4,1,360,1,4) AXIS(0)")
    run_to(c, 0.0025)
    _master(c, speed=3600.0)  # 10 cycles a second
    run_to(c, 0.5)
    assert c.axis(0)["mtype"] == 20
    c.terminal("REP_OPTION AXIS(0)=2")
    run_to(c, 1.0)
    (t_end, _f), = fields(c, "move_end", axis=0)
    assert c.axis(0)["dpos"] == 0.0  # the cam's end: back to its start
    assert 0.5 < t_end <= 0.61
    assert c.terminal("? REP_OPTION AXIS(0)").reply == "0.0000"


def test_cambox_md_option_2_starts_at_link_pos():
    c = make()
    c.terminal("TABLE(0,0,100)")
    _master(c)
    c.terminal("CAMBOX(0,1,1,100,1,2,500) AXIS(0)")
    run_to(c, 0.45)
    assert c.axis(0)["dpos"] == 0.0 and c.axis(0)["mtype"] == 20
    run_to(c, 0.7)
    assert c.axis(0)["dpos"] == 100.0 and c.axis(0)["mtype"] == 0


def test_cambox_md_pattern_mode_scales_each_cycle_by_the_pattern_and_repeats():
    """Shape 0..100 edges (TABLE 0..1); pattern TABLE(50..52) = 1, 2, 3; control block at 20:
    current 50, force -1, first 50, last 52, repeat position 0, repeat count 2, next -1.
    Two passes of the pattern (6 cycles of 100 link units) then the CAMBOX ends: the slave
    has moved (1+2+3) x 2 x 100 = 1200; the control block counted the repeats."""
    c = make()
    c.terminal("TABLE(0,0,100)")
    c.terminal("TABLE(50,1,2,3)")
    c.terminal("TABLE(20,50,-1,50,52,0,2,-1)")
    c.terminal("CAMBOX(0,1,20,100,1,12) AXIS(0)")
    run_to(c, 0.0025)
    _master(c)
    run_to(c, 0.1505)  # in the 2nd cycle (multiplier 2)
    m = c.axis(1)["dpos"]
    assert 100 < m < 200
    assert c.axis(0)["dpos"] == pytest.approx(100 + 2 * (m - 100))
    assert c.get_variable("TABLE(20)") == 51.0
    run_to(c, 1.0)
    assert c.axis(0)["mtype"] == 0
    assert c.axis(0)["dpos"] == pytest.approx(1200.0)
    assert c.get_variable("TABLE(24)") == 2.0


def test_cambox_md_pattern_repeat_count_0_stops_at_the_end_of_the_pattern():
    c = make()
    c.terminal("TABLE(0,0,10)")
    c.terminal("TABLE(50,1,1)")
    c.terminal("TABLE(20,50,-1,50,51,0,-1,-1)")  # endless
    c.terminal("CAMBOX(0,1,20,10,1,12) AXIS(0)")
    run_to(c, 0.0025)
    _master(c, speed=100.0)
    run_to(c, 1.0)
    assert c.axis(0)["mtype"] == 20
    c.terminal("TABLE(25,0)")
    run_to(c, 2.0)
    assert c.axis(0)["mtype"] == 0
    assert c.axis(0)["dpos"] % 20 == 0  # whole patterns of two 10-edge cycles


@pytest.mark.parametrize(("cmd", "text"), [
    ("CAMBOX(0,1,16383,100,1,12) AXIS(0)", "control block"),  # 7 values do not fit
    ("MOVELINK(10,10,0,0,1,16+5*1024) AXIS(0)", "curve 5"),  # bits 10..12 = 5: unused
    ("MOVELINK(10,10,0,0,1,64) AXIS(0)", "link_options 64"),  # bit 6 is reserved
    ("CAMBOX(0,1,1,100,1,0,0,5) AXIS(0)", "offset_start"),
])
def test_bad_link_options_are_run_time_errors_that_buffer_nothing(cmd, text):
    c = make()
    c.terminal("TABLE(0,0,100)")
    r = c.terminal(cmd)
    assert r.error is not None and text in r.error
    run_to(c, 0.01)
    assert fields(c, "move_start") == []


@pytest.mark.parametrize(("model", "start"), [("mc4xx", 0.0), ("mc2xx", 1000.0)])
def test_cambox_md_mc4_offsets_the_table_by_its_first_value(model, start):
    """MC4 help: the TABLE values are offset by the first one, then multiplied, so the cam
    starts where the axis is; the MC2xx TRM takes them as positions from the start."""
    c = make(model=model)
    c.terminal("TABLE(0,1000,1100,1200)")
    c.terminal("CAMBOX(0,2,1,100,1) AXIS(0)")
    run_to(c, 0.0025)
    assert c.axis(0)["dpos"] == start
    c.terminal("MOVE(100) AXIS(1)")
    run_to(c, 1.0)
    assert c.axis(0)["dpos"] == start + 200.0
