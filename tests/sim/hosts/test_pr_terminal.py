"""A PR-polling host that asks ``PR`` on the card's command line (the real PMAC core): its
replies come at the end of a background cycle, a busy card answers late or not at all, and a
card whose watchdog tripped stops the host."""

from __future__ import annotations

import random

import pytest
from motionsim.sim.hosts import CpuMonitor, PrPollingHost, fixed
from motionsim.sim.pmac import PmacController

MOVES = ["LINEAR", "ABS", "TA2", "TS0", "TM2", *(f"X{k}" for k in range(1, 2001))]


def card(**config) -> PmacController:
    ctl = PmacController("pmac", config)
    ctl.define_rotary(1, 6000)
    return ctl


def host(ctl: PmacController, **kw) -> PrPollingHost:
    h = PrPollingHost(
        "h", ctl, 1, MOVES, random.Random(1), poll_period_s=0.01, lines_per_write=50,
        high_water=200, low_water=100, via_terminal=True, **kw,
    )  # fmt: skip
    h.start()
    return h


def plc0(ctl: PmacController, statements: int) -> None:
    ctl.plcs.load(0, "\n".join(["P1=P1+1"] * statements))
    ctl.plcs.set_enabled((0,), True)


def test_pr_is_answered_in_the_next_servo_cycle_by_an_idle_card():
    ctl = card()
    h = host(ctl)
    ctl.env.run(until=0.5)
    prs = ctl.log.events("host_pr")
    assert len(prs) == 50
    period = ctl.scheduler.period_s
    # polls start on a 10 ms grid (not on servo cycles): the reply comes at the end of the
    # background cycle in progress — the next servo cycle, or the one after when the 40 µs
    # of command and housekeeping no longer fit before it
    assert all(0 < e.fields["reply_s"] <= period + 40e-6 for e in prs)
    assert sum(e.fields["reply_s"] for e in prs) / len(prs) < period
    assert h.replies == [e.fields["reply_s"] for e in prs]
    # the count read is the card's PR: before the first write, 0; later, what was loaded
    assert prs[0].fields["lines_ahead"] == 0 and prs[1].fields["lines_ahead"] > 100
    assert ctl.log.events("host_timeout") == []
    assert ctl.coord(1)["program"]["state"] == "running"


def test_pr_replies_wait_for_background_time_behind_plc0():
    idle, busy = card(), card()
    plc0(busy, 300)  # ≈ 1.0 ms of each 1.33 ms RTI period
    host(idle), host(busy)
    idle.env.run(until=0.5)
    busy.env.run(until=0.5)
    mean = [
        sum(e.fields["reply_s"] for e in c.log.events("host_pr")) / len(c.log.events("host_pr"))
        for c in (idle, busy)
    ]
    assert mean[1] > 2 * mean[0]
    assert busy.log.events("watchdog") == []


def test_an_unanswered_pr_times_out_and_the_host_polls_again():
    ctl = card(i40=100_000)  # PLC 0 longer than the RTI, watchdog kept out of the way
    h = host(ctl, reply_timeout_s=0.05)
    ctl.env.run(until=0.1)
    plc0(ctl, 500)
    ctl.env.run(until=0.5)
    outs = [e for e in ctl.log.events("host_timeout") if e.t > 0.1]
    assert len(outs) >= 5 and h.timeouts == len(outs)
    assert all(e.fields["waited_s"] == pytest.approx(0.05) for e in outs)
    assert all(e.fields["command"] == "&1PR" for e in outs)
    assert not [e for e in ctl.log.events("host_pr") if e.t > 0.11]


def test_a_tripped_card_stops_the_host():
    ctl = card()
    h = host(ctl, reply_timeout_s=0.05)
    ctl.env.run(until=0.1)
    plc0(ctl, 500)
    ctl.env.run(until=2.5)
    (trip,) = ctl.log.events("watchdog")
    (stop,) = ctl.log.events("host_stopped")
    assert trip.t < stop.t <= trip.t + 0.06  # the next poll after the trip is refused
    assert "watchdog" in stop.fields["reason"] and h.stopped
    writes = ctl.log.events("host_write")
    ctl.env.run(until=3.0)
    assert ctl.log.events("host_write") == writes and h.remaining == 0


def test_the_cpu_monitor_samples_the_load_on_its_grid_until_the_trip():
    ctl = card()
    CpuMonitor(ctl, 0.1).start()
    ctl.env.run(until=0.35)
    plc0(ctl, 500)
    ctl.env.run(until=3.0)
    samples = ctl.log.events("cpu_sample")
    (trip,) = ctl.log.events("watchdog")
    grid = [round(0.1 * k, 9) for k in range(1, len(samples) + 1)]
    assert [round(e.t, 9) for e in samples] == grid
    assert samples[-1].t < trip.t < samples[-1].t + 0.1  # none after the trip
    assert samples[0].fields["plc0_statements"] == 0
    assert samples[-1].fields["plc0_statements"] == 500
    assert samples[-1].fields["rti"] > 0.99
    assert set(samples[0].fields) == {"servo", "rti", "background", "background_cycle_s",
                                      "plc0_statements"}  # fmt: skip


def test_reading_pr_directly_still_works_without_the_terminal():
    ctl = card()
    h = PrPollingHost("h", ctl, 1, MOVES, random.Random(1), poll_period_s=0.01,
                      pr_latency=fixed(0.001), high_water=200, low_water=100)  # fmt: skip
    h.start()
    ctl.env.run(until=0.2)
    assert ctl.log.events("host_pr") == [] and h.sent >= 200
