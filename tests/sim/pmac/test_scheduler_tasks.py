"""Task priorities and processor time: servo > RTI (planning, PLC 0) > background.

Seed 003: PLC 0 runs every RTI (every I8+1 servo cycles) as long as the previous RTI's tasks
have finished; the background (one PLC 1-31 scan, housekeeping, a host command) gets what is
left, so it cycles slower as PLC 0 grows, and the host's replies come later. Costs are
:class:`motionsim.sim.pmac.tasks.cpu.CpuCosts` (3.3 µs per interpreted statement, 5 µs per scan, 20
µs per
host command and per housekeeping pass).
"""

from __future__ import annotations

import pytest
from motionsim.sim.pmac.tasks.cpu import CpuCosts


def plc0(rig, statements: int) -> None:
    """PLC 0 of ``statements`` statements, the first counting scans in M1."""
    rig.c.plcs.load(0, "\n".join(["M1=M1+1"] + ["P10=P10+1"] * (statements - 1)))
    rig.ok("ENABLE PLC 0")


def count(rig, name: str, t0: float) -> int:
    return sum(1 for e in rig.c.log.read(0, ["mvar"]).events if e["name"] == name and e.t >= t0)


@pytest.mark.parametrize("i8", [2, 0, 5])
def test_plc0_runs_once_per_rti(make_rig, i8):
    """Over one second PLC 0 scans servo_hz / (I8+1) times, each on an RTI cycle."""
    rig = make_rig(i8=i8)
    plc0(rig, 10)
    t0 = rig.c.now
    rig.run_for(1.0)
    scans = [(c, e) for c, _, e in rig.events("mvar") if e["name"] == "M1"]
    servo_hz = 1.0 / rig.period
    assert abs(len(scans) - servo_hz / (i8 + 1)) <= 1
    assert all(c % (i8 + 1) == 0 for c, _ in scans)
    assert scans[0][0] == (rig.cyc(t0) // (i8 + 1) + 1) * (i8 + 1)  # the first RTI after
    assert rig.events("rti_overrun") == []


def background_rate(make_rig, plc0_statements: int) -> int:
    rig = make_rig(i5=3)
    rig.c.plcs.load(1, "M2=M2+1")
    rig.ok("ENABLE PLC 1")
    if plc0_statements:
        plc0(rig, plc0_statements)
    t0 = rig.c.now
    rig.run_for(1.0)
    return count(rig, "M2", t0)


def test_a_background_plc_scans_slower_as_plc0_grows(make_rig):
    """Seed 003: the more high-priority work, the slower the background cycles."""
    rates = [background_rate(make_rig, n) for n in (0, 200, 300, 395)]
    servo_hz = 1.0 / make_rig().period
    assert abs(rates[0] - servo_hz) <= 2  # light load: one background cycle per servo cycle
    assert rates[0] > rates[1] > rates[2] > rates[3] > 0
    # 200 statements ≈ 665 µs of each 1.33 ms RTI period: two of three servo cycles left.
    assert abs(rates[1] - servo_hz * 2 / 3) <= 2
    assert abs(rates[2] - servo_hz / 3) <= 2


def reply_cycles(make_rig, plc0_statements: int) -> int:
    rig = make_rig()
    if plc0_statements:
        plc0(rig, plc0_statements)
    rig.run_for(0.1)
    # Send the poll at an RTI instant, before that RTI's tasks run.
    k = (rig.cyc(rig.c.scheduler.next_rti_after(rig.c.now)))
    rig.c.env.run(until=k * rig.period)
    reply = rig.c.terminal("PR")
    while not reply.done:
        rig.c.env.step()
    return rig.cyc(reply.t_done) - k


def test_host_reply_latency_grows_with_plc0(make_rig):
    """A host polling ``PR`` sees PLC 0's load: the reply waits for processor time."""
    got = [reply_cycles(make_rig, n) for n in (0, 100, 200, 300, 395)]
    assert got[0] == 1
    assert got == sorted(got) and got[-1] > got[0]
    costs = CpuCosts()
    for n, cycles in zip((100, 200, 300), got[1:4], strict=True):
        work = costs.plc_scan_s + n * costs.plc_statement_s + costs.rti_base_s
        work += costs.host_command_s + costs.housekeeping_s
        assert (cycles - 1) * make_rig().period < work <= cycles * make_rig().period


def test_plc0_longer_than_the_rti_period_overruns_every_rti(make_rig):
    """PLC 0 runs only when the previous RTI's tasks finished: ``rti_overrun`` events."""
    rig = make_rig(i40=100000)  # keep the watchdog out of this test
    plc0(rig, 500)  # ≈ 1.66 ms > 1.33 ms
    t0 = rig.c.now
    rig.run_for(0.1)
    over = [c for c, _, _ in rig.events("rti_overrun")]
    scans = count(rig, "M1", t0)
    rti = 0.1 / rig.c.scheduler.rti_period_s()
    assert len(over) >= rti - 2  # every RTI after the first finds PLC 0 still running
    assert scans < rti  # fewer scans than RTIs: the overrun RTIs are latched, not stacked
    assert all(c % 3 == 0 for c in over)
    assert all(e["over_s"] > 0 for _, _, e in rig.events("rti_overrun"))


def test_the_load_figure(make_rig):
    rig = make_rig()
    rig.ok("#1->X #2->Y")
    plc0(rig, 200)
    rig.run_for(1.5)
    cpu = rig.c.status()["cpu"]
    assert cpu["servo"] == pytest.approx(2 * 4.4e-6 / rig.period)
    rti = (5e-6 + 200 * 3.3e-6 + 2e-6) / rig.c.scheduler.rti_period_s()
    assert cpu["rti"] == pytest.approx(rti, rel=0.02)
    assert cpu["background"] == pytest.approx(1 - cpu["servo"] - cpu["rti"])
    assert cpu["background_cycle_s"] >= rig.period


def test_costs_are_configurable(make_rig):
    """``cpu_plc_statement_us``: 10 µs per statement makes 200 statements overrun."""
    rig = make_rig(cpu_plc_statement_us=10, i40=100000)
    assert rig.c.background.costs.plc_statement_s == pytest.approx(10e-6)
    plc0(rig, 200)
    rig.run_for(0.05)
    assert rig.events("rti_overrun")


def test_without_plcs_the_processor_model_sleeps(rig):
    """No PLC, no host command: no scheduled wake-ups (the rotary hot path is untouched)."""
    rig.ok("I16")
    rig.run_until_idle(limit_s=5.0)
    assert rig.c.env.peek() == float("inf")


def test_every_plc_effect_falls_on_a_servo_cycle(make_rig):
    """Enabling a background PLC between servo cycles: its scans still start on cycles."""
    rig = make_rig(i5=3)
    rig.c.plcs.load(1, "M2=M2+1")
    rig.run_for(0.0101)  # between two servo cycles
    rig.c.plcs.set_enabled((1,), True)
    rig.run_for(0.01)
    cycles = [c for c, _, f in rig.events("mvar")]  # rig.cyc asserts whole cycles
    assert len(cycles) > 10 and cycles == sorted(set(cycles))


def test_an_rti_overrun_sets_the_real_time_interrupt_warning_bit(rig):
    """TSRM p290: ``???`` first word bit 9 = real-time interrupt warning (latched)."""
    assert rig.ok("???") == "000000000000"
    # One long scan (the 20th), then short ones: the host can read the status again.
    rig.c.plcs.load(0, "P1=P1+1\nIF (P1=20)\n" + "P10=P10+1\n" * 500 + "ENDIF")
    rig.ok("ENABLE PLC 0")
    rig.run_for(0.1)
    assert len(rig.events("rti_overrun")) == 1
    assert rig.ok("???") == "000200000000"


def _overruns_with_motors(make_rig, motors: int, statements: int) -> int:
    rig = make_rig(i40=100000)
    if motors:
        rig.ok(" ".join(f"#{m}->{axis}" for m, axis in zip(range(1, motors + 1), "XYZUVWAB",
                                                             strict=False)))
    plc0(rig, statements)
    rig.run_for(0.1)
    return len(rig.events("rti_overrun"))


def test_servo_updates_of_the_defined_motors_take_time_from_the_rti_tasks(make_rig):
    """Servo > RTI: each defined motor's servo update (≈ 1 % of the processor, 4.4 µs per
    cycle) is taken first, so the RTI tasks get only what is left of each cycle. PLC 0 of 385
    statements (≈ 1.28 ms) fits the 1.33 ms RTI period of a card with no motors, but not of
    one with 8 motors (≈ 8 % of each cycle gone: ≈ 1.22 ms left)."""
    assert _overruns_with_motors(make_rig, 0, 385) == 0
    assert _overruns_with_motors(make_rig, 8, 385) > 0
    assert _overruns_with_motors(make_rig, 8, 340) == 0
