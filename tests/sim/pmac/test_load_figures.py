"""Load figures of ``status()``: when the last background cycle completed, the watchdog's
reload margin (I40 counter, TSRM p57; spec §9.6), per-PLC statements per scan."""

from __future__ import annotations

import pytest


def test_idle_controller_has_the_whole_watchdog_margin(rig):
    rig.run_for(0.01)
    wd = rig.c.status()["watchdog"]
    assert wd["limit_cycles"] == 4096 and wd["cycles_left"] == 4096
    assert rig.cyc(wd["reload_s"]) == rig.c.scheduler.clock.index(rig.c.env.now)
    assert rig.c.status()["plcs"] == {}


def test_last_background_cycle_is_the_answer_to_a_host_command(rig):
    assert rig.c.status()["cpu"]["last_background_s"] is None
    reply = rig.cmd("I5")
    assert rig.c.status()["cpu"]["last_background_s"] == pytest.approx(reply.t_done)


def test_plc_statements_per_scan_and_scans(rig):
    rig.ok("I5=3")
    rig.c.plcs.load(2, "P1=P1+1\nP2=P2+1\nP3=P3+1")
    rig.ok("ENABLE PLC 2")
    rig.run_for(0.05)
    plc = rig.c.status()["plcs"]["2"]
    assert plc["statements_last_scan"] == 3
    assert plc["scans"] == rig.c.plcs.plcs[2].scans > 10
    cpu = rig.c.status()["cpu"]
    assert rig.c.env.now - cpu["last_background_s"] < 0.005  # background keeps cycling


def test_a_starving_plc0_runs_the_margin_down_to_the_trip(make_rig):
    rig = make_rig(i40=300)
    rig.c.plcs.load(0, "\n".join(["M1=M1+1"] + ["P10=P10+1"] * 499))
    k_enable = rig.cyc(rig.cmd("ENABLE PLC 0").t_done)
    rig.run_for(100 * rig.period)
    wd = rig.c.status()["watchdog"]
    assert rig.cyc(wd["reload_s"]) == k_enable + 1  # the last housekeeping pass
    k_now = rig.c.scheduler.clock.index(rig.c.env.now)
    assert wd["cycles_left"] == k_enable + 1 + 300 - k_now
    rig.run_for(0.5)
    wd = rig.c.status()["watchdog"]
    assert wd["tripped"] is True and wd["cycles_left"] == 0
    assert rig.cyc(wd["t"]) == k_enable + 1 + 300


@pytest.mark.parametrize(("i40", "cycles"), [(0, 4096), (1, 1), (2, 2), (300, 300)])
def test_the_watchdog_limit_is_i40_servo_cycles_and_0_selects_4096(make_rig, i40, cycles):
    """TSRM p57: I40 is the watchdog time in servo cycles; 0 means the default 4096."""
    wd = make_rig(i40=i40).c.status()["watchdog"]
    assert wd["limit_cycles"] == cycles and wd["cycles_left"] == cycles


def test_the_margin_counts_from_the_last_reload_late_in_a_run(make_rig):
    """The same margin after 2 s of idle running (servo cycle numbers past 4096)."""
    rig = make_rig(i40=300)
    rig.run_for(2.0)
    rig.c.plcs.load(0, "\n".join(["M1=M1+1"] + ["P10=P10+1"] * 499))
    k_enable = rig.cyc(rig.cmd("ENABLE PLC 0").t_done)
    assert k_enable > 4096
    rig.run_for(100 * rig.period)
    wd = rig.c.status()["watchdog"]
    assert rig.cyc(wd["reload_s"]) == k_enable + 1
    k_now = rig.c.scheduler.clock.index(rig.c.env.now)
    assert wd["cycles_left"] == k_enable + 1 + 300 - k_now


def test_each_defined_motor_takes_about_one_percent_of_the_processor(rig):
    """Seed 003: at the default 2.25 kHz servo clock the servo update of each motor takes
    about 1 % of the processor; a motor counts once it is assigned to an axis."""
    assert rig.c.status()["cpu"]["servo"] == 0.0
    for motor, axis in enumerate("XYZABCUV", start=1):
        rig.ok(f"&1 #{motor}->{axis}")
    rig.run_for(0.05)
    cpu = rig.c.status()["cpu"]
    assert cpu["servo"] == pytest.approx(0.08, abs=0.004)
    assert cpu["background"] == pytest.approx(1.0 - cpu["servo"] - cpu["rti"], abs=1e-9)


def test_the_margin_is_zero_cycles_on_the_trip_cycle_itself(make_rig):
    """``cycles_left`` counts servo cycles to the trip: read on the trip cycle, before the
    card has acted on it, none are left (not one)."""
    rig = make_rig(i40=300)
    rig.c.plcs.load(0, "\n".join(["M1=M1+1"] + ["P10=P10+1"] * 499))
    k_trip = rig.cyc(rig.cmd("ENABLE PLC 0").t_done) + 1 + 300
    rig.c.env.run(until=rig.c.scheduler.clock.t(k_trip))
    wd = rig.c.status()["watchdog"]
    assert wd["tripped"] is False and wd["cycles_left"] == 0
    rig.run_for(rig.period)
    assert rig.c.status()["watchdog"]["tripped"] is True
