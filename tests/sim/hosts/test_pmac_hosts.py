"""Rotary-buffer host models against a stand-in PMAC: BREQ service in time or too late,
the missed BREQ, PR polling with water marks, the naive writer; determinism."""

from __future__ import annotations

import random

from motionsim.app.scenarios.report import pmac_report
from motionsim.sim.hosts import BreqInterruptHost, Delay, NaiveHost, PrPollingHost, fixed

from tests.sim.hosts.fake_pmac import FakePmac

LINES = [f"X{k}" for k in range(1, 401)]


def run_breq(latency: Delay, *, seed: int = 1, recheck: bool = True, per_irq: int = 10):
    pmac = FakePmac(i16=5, i17=10, move_s=0.001)
    host = BreqInterruptHost(
        "h", pmac, 1, LINES, random.Random(seed),
        latency=latency, lines_per_interrupt=per_irq, recheck_breq=recheck,
    )  # fmt: skip
    host.start()
    pmac.env.run(until=1.0)
    rep = pmac_report(pmac.log.events(), 1.0, i16=5, total_lines={1: len(LINES)})
    return pmac, host, rep


def test_breq_host_within_i16_lines_never_starves():
    # Below I16 = 5 there are 4 lines ahead plus the executing move: ~4 ms of motion.
    _, host, rep = run_breq(fixed(0.002))
    cs = rep["cs"][1]
    assert host.sent == len(LINES)
    assert cs["starvations"] == 0 and cs["time_starved_s"] == 0
    assert cs["lines_executed"] == len(LINES)
    assert cs["min_lines_ahead"] >= 3
    assert cs["host_interrupts"] > 0 and cs["breq_missed"] == 0


def test_breq_host_slower_than_i16_lines_starves_and_is_diagnosed_as_latency():
    _, _, rep = run_breq(fixed(0.008))
    cs = rep["cs"][1]
    assert cs["starvations"] > 0
    assert cs["time_starved_s"] > 0
    first = rep["starvation_list"][0]
    assert first.cause == "host_latency"
    assert first.facts["host_response_s"] > first.facts["covered_s"]
    assert abs(first.facts["host_response_s"] - 0.008) < 1e-9


def test_service_routine_without_recheck_misses_breq_and_starves_for_good():
    pmac, host, rep = run_breq(fixed(0.0005), recheck=False, per_irq=1)
    cs = rep["cs"][1]
    assert cs["breq_missed"] >= 1
    assert host.sent < len(LINES)  # nothing ever interrupted it again
    last = rep["starvation_list"][-1]
    assert last.cause == "breq_missed"
    assert last.end == 1.0  # still starved at the end of the run


def test_same_seed_same_log_and_other_seed_differs():
    jitter = Delay("normal", 0.002, 0.001)
    a, _, _ = run_breq(jitter, seed=7)
    b, _, _ = run_breq(jitter, seed=7)
    c, _, _ = run_breq(jitter, seed=8)
    assert a.log.to_jsonl() == b.log.to_jsonl()
    assert a.log.to_jsonl() != c.log.to_jsonl()


def test_host_events_record_each_interrupt_and_write():
    pmac, host, _ = run_breq(fixed(0.002))
    irqs = pmac.log.events("host_irq")
    writes = pmac.log.events("host_write")
    assert len(irqs) == host.interrupts
    assert all(abs(e["latency_s"] - 0.002) < 1e-12 for e in irqs)
    assert sum(e["lines"] for e in writes) == len(LINES)
    assert pmac.log.events("host_done")[0]["sent"] == len(LINES)


def run_poll(period_s: float, low: int, high: int):
    pmac = FakePmac(i16=5, i17=10, move_s=0.001)
    host = PrPollingHost(
        "p", pmac, 1, LINES, random.Random(1),
        poll_period_s=period_s, lines_per_write=5, high_water=high, low_water=low,
    )  # fmt: skip
    host.start()
    pmac.env.run(until=1.0)
    return pmac, host, pmac_report(pmac.log.events(), 1.0, i16=5, total_lines={1: len(LINES)})


def test_pr_polling_refills_from_low_to_high_water():
    pmac, host, rep = run_poll(0.005, low=20, high=40)
    assert rep["cs"][1]["starvations"] == 0
    loaded = pmac.log.events("line_loaded")
    assert max(e["lines_ahead"] for e in loaded) == 40
    assert host.sent == len(LINES)


def test_pr_polling_slower_than_low_water_lasts_starves():
    # 10 lines at low water last ~10 ms; polling every 30 ms cannot keep up.
    _, _, rep = run_poll(0.030, low=10, high=20)
    assert rep["cs"][1]["starvations"] > 0
    assert rep["starvation_list"][0].cause == "host_latency"


def test_naive_writer_fills_to_the_buffer_size():
    pmac = FakePmac(size=50, move_s=0.001)
    host = NaiveHost("n", pmac, 1, LINES, random.Random(1), lines_per_write=7,
                     write_latency=fixed(0.0001))  # fmt: skip
    host.start()
    pmac.env.run(until=1.0)
    assert host.sent == len(LINES)
    assert max(e["lines_ahead"] for e in pmac.log.events("line_loaded")) >= 45
    rep = pmac_report(pmac.log.events(), 1.0, total_lines={1: len(LINES)})
    assert rep["cs"][1]["starvations"] == 0


def test_host_stall_fault_delays_writes():
    pmac = FakePmac()
    host = BreqInterruptHost("h", pmac, 1, LINES, random.Random(1), lines_per_interrupt=10)
    host.start()
    host.stall(0.05)
    pmac.env.run(until=0.2)
    first = pmac.log.events("host_write")[0]
    assert first.t == 0.05
