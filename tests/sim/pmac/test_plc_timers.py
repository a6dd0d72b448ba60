"""Countdown timers Isx11 / Isx12 (TSRM p176; spec §12.3), asserted on the event log.

Times in servo cycles (``rig.cyc``): the timer drops by one every servo cycle, so the
universal wait ``I5111=t*8388608/I10`` + ``WHILE(I5111>0) ENDWHILE`` lasts ceil(t / servo
period) cycles.
"""

from __future__ import annotations

import math

import pytest


def enter(rig, *lines: str, n: int = 1) -> None:
    rig.ok(f"OPEN PLC {n} CLEAR")
    for line in lines:
        rig.ok(line)
    rig.ok("CLOSE")


def m_events(rig, name: str) -> list[tuple[int, float]]:
    return [(k, f["value"]) for k, _, f in rig.events("mvar") if f["name"] == name]


@pytest.mark.parametrize(("timer", "ms"), [("I5111", 100), ("I5112", 250), ("I5211", 7)])
def test_tsrm_p176_isx11_wait_in_a_plc_takes_its_programmed_time(rig, timer, ms):
    rig.ok("I5=2")
    enter(rig, "M1=1", f"{timer}={ms}*8388608/I10", f"WHILE({timer}>0)", "ENDWHILE", "M1=0",
          "DISABLE PLC 1")
    rig.ok("ENABLE PLC 1")
    rig.run_for(ms / 1000 + 0.05)
    (k1, v1), (k0, v0) = m_events(rig, "M1")
    servo_ms = rig.period * 1000
    assert (v1, v0) == (1, 0)
    assert k0 - k1 == math.ceil(ms / servo_ms)


def test_tsrm_p176_isx11_counts_down_every_servo_cycle(rig):
    rig.ok("I5112=1000")
    t0 = rig.cyc(rig.c.env.now)
    rig.run_for(rig.period * 40)
    t1 = rig.cyc(rig.c.env.now)
    # a query is answered one background cycle later: read the value at that instant
    reply = rig.cmd("I5112")
    t2 = rig.cyc(rig.c.env.now)
    assert t1 - t0 == 40
    assert int(reply.reply) == 1000 - (t2 - t0)


def test_tsrm_p176_isx12_goes_below_zero_and_stops_at_minus_2_pow_23(rig):
    rig.ok("I5212=-8388600")
    rig.run_for(rig.period * 100)
    assert rig.ok("I5212") == "-8388608"
    rig.ok("I5211=3")
    rig.run_for(rig.period * 20)
    assert int(rig.ok("I5211")) < -10


def test_tsrm_p176_a_cs_not_activated_by_i68_holds_its_timer(make_rig):
    rig = make_rig(**{"i68": 1})  # CS 1 and 2 active
    rig.ok("I5311=500 I5211=500")
    rig.run_for(rig.period * 30)
    assert rig.ok("I5311") == "500"
    assert int(rig.ok("I5211")) < 475


def test_tsrm_p176_timer_written_with_a_fraction_is_a_whole_number(rig):
    rig.ok("I5111=10.6")
    assert rig.ok("I5111") in ("11", "10")


def test_each_timer_write_is_a_timer_event_with_the_stored_value(rig):
    """API.md event table: a write of Isx11 / Isx12 is a ``timer`` event naming the variable
    and the whole number of servo cycles stored (TSRM p176: the register holds an integer)."""
    rig.ok("I5111=100.4")
    rig.ok("I6612=-7")
    assert [(f["var"], f["value"]) for _, _, f in rig.events("timer")] == [
        ("I5111", 100.0), ("I6612", -7.0)]


def test_tsrm_p176_a_held_timer_keeps_its_top_value_and_clamps_above_it(rig):
    """With I68=0 only CS 1 is activated, so CS 2's Isx11 holds what was written: the
    largest 24-bit value, 8 388 607, and a larger write stored as that."""
    rig.ok("I68=0")
    rig.ok("I5211=8388607")
    rig.run_for(rig.period * 20)
    assert rig.ok("I5211") == "8388607"
    rig.ok("I5211=9000000")
    assert rig.ok("I5211") == "8388607"


def test_tsrm_p176_i68_decides_which_cs_timers_count(rig):
    """I68=11: CSs 1..12 are activated: CS 12's timer counts down, CS 13's holds."""
    rig.ok("I68=11")
    rig.ok("I6211=1000 I6311=1000")
    rig.run_for(rig.period * 50)
    assert int(rig.ok("I6211")) < 1000
    assert rig.ok("I6311") == "1000"


def test_i5011_is_no_timer(rig):
    """Isx11 / Isx12 exist for CS 1..16 only: I5011 is an ordinary I-variable (it keeps its
    value)."""
    rig.ok("I5011=100")
    rig.run_for(rig.period * 40)
    assert rig.ok("I5011") == "$64"
    assert rig.events("timer") == []
