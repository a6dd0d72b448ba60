"""The special lookahead buffer: ``DEFINE LOOKAHEAD`` / ``DELETE LOOKAHEAD`` and their
ordering rules (TSRM p308, p315; spec §1.3), and what it changes when active (Isx13 > 0,
buffer defined, Isx20 > 0): Ixx16 / Ixx17 apply to segmented LINEAR moves (TSRM p98 regime 2)
and calculation runs Isx20 segments ahead (TSRM p181). X is motor 1 at 1000 counts per unit;
times in servo cycles."""

from __future__ import annotations

import math

import pytest
from motionsim.sim.pmac.buffers.lookahead_buffer import LookaheadBuffer


def _err(rig, text):
    reply = rig.cmd(text)
    return reply.error


def _la(rig, cs=1):
    return rig.c.coord_system(cs).lookahead


def test_tsrm_p308_define_lookahead_reserves_segments_and_outputs_for_the_addressed_cs(rig):
    rig.ok("&2 DEFINE LOOKAHEAD 50,10")
    rig.ok("&1 DEF LOOK 20,4")
    assert _la(rig, 2) == LookaheadBuffer(50, 10)
    assert _la(rig, 1) == LookaheadBuffer(20, 4)
    assert _la(rig, 3) is None


def test_tsrm_p308_define_lookahead_is_refused_while_a_rotary_buffer_exists(rig):
    rig.ok("&2 DEFINE ROT 100")
    assert _err(rig, "&1 DEFINE LOOKAHEAD 50,10") == "ERR003"
    assert _la(rig) is None


def test_tsrm_p308_define_lookahead_is_refused_while_a_gather_buffer_exists(rig):
    rig.ok("DEFINE GATHER 100")
    assert _err(rig, "&1 DEFINE LOOKAHEAD 50,10") == "ERR003"
    assert _la(rig) is None


def test_tsrm_p315_lookahead_buffers_are_defined_from_the_highest_cs_down(rig):
    """The DLS Geo Brick PLC1 order: &16 first, then lower ones."""
    rig.ok("&2 DEFINE LOOKAHEAD 50,10")
    assert _err(rig, "&3 DEFINE LOOKAHEAD 50,10") == "ERR003"  # CS 2 (lower) already has one
    assert _la(rig, 3) is None
    rig.ok("&1 DEFINE LOOKAHEAD 50,10")


def test_tsrm_p315_lookahead_buffers_are_deleted_from_the_lowest_cs_up(rig):
    rig.ok("&3 DEFINE LOOKAHEAD 50,10")
    rig.ok("&2 DEFINE LOOKAHEAD 50,10")
    assert _err(rig, "&3 DELETE LOOKAHEAD") == "ERR003"  # CS 2 still has one
    assert _la(rig, 3) is not None
    rig.ok("&2 DEL LOOK")
    rig.ok("&3 DELETE LOOKAHEAD")
    assert _la(rig, 2) is None and _la(rig, 3) is None


def test_tsrm_p315_delete_lookahead_is_refused_while_a_rotary_buffer_exists(rig):
    rig.ok("&1 DEFINE LOOKAHEAD 50,10")
    rig.ok("&1 DEFINE ROT 100")
    assert _err(rig, "&1 DELETE LOOKAHEAD") == "ERR003"
    assert _la(rig) == LookaheadBuffer(50, 10)


def test_tsrm_p315_lookahead_buffers_are_not_kept_through_a_reset(rig):
    rig.ok("&1 DEFINE LOOKAHEAD 50,10")
    rig.ok("SAVE")
    rig.ok("$$$")
    rig.run_for(0.01)  # the reset acts after the command's background cycle
    assert _la(rig) is None


@pytest.mark.parametrize(
    "text", ["&1 DEFINE LOOKAHEAD 50", "&1 DEFINE LOOKAHEAD 0,10", "&1 DEFINE LOOKAHEAD ,10"]
)
def test_a_malformed_define_lookahead_answers_err003_and_defines_nothing(rig, text):
    assert _err(rig, text) == "ERR003"
    assert _la(rig) is None


def _lookahead_setup(rig, isx20=10, *cmds, lookahead=True):
    rig.ok("&1 #1->1000X")
    rig.ok("I5113=10")
    rig.ok(f"I5120={isx20}")
    if lookahead:
        rig.ok("&1 DEFINE LOOKAHEAD 50,10")
    rig.rotary_setup()
    for c in cmds:
        rig.ok(c)


def _run(rig, lines):
    rig.c.load_lines(1, lines)
    rig.ok("R")
    rig.run_until_idle()


def _span(rig, n=1):
    start = {f["n"]: k for k, _, f in rig.events("move_start")}
    end = {f["n"]: k for k, _, f in rig.events("move_end")}
    return end[n] - start[n]


def test_tsrm_p98_segmented_linear_with_the_special_lookahead_obeys_ixx16(rig):
    """TM100 X10 asks 100 counts/ms; Ixx16 = 20 makes it 500 ms (+ Ta 10 ms)."""
    _lookahead_setup(rig, 10, "I116=20", "I117=1000")
    _run(rig, ["LINEAR ABS TA10 TS0 TM100 X10"])
    assert _span(rig) == math.ceil(0.510 / rig.period - 1e-6)


def test_tsrm_p98_with_isx20_0_the_lookahead_buffer_alone_does_not_limit(rig):
    _lookahead_setup(rig, 0, "I116=20", "I117=1000")
    _run(rig, ["LINEAR ABS TA10 TS0 TM100 X10"])
    assert _span(rig) == pytest.approx(rig.ms_cycles(110), abs=1)


def test_mode_3_a_start_from_rest_and_the_final_stop_obey_ixx17(rig):
    """TM1000 TA100 X10 (10 counts/ms) at Ixx17 = 0.05: ramp up and stop each 200 ms, the
    move 1200 ms from start to stop (1100 ms without the lookahead)."""
    _lookahead_setup(rig, 10, "I116=1000", "I117=0.05")
    _run(rig, ["LINEAR ABS TA100 TS0 TM1000 X10"])
    assert _span(rig) == math.ceil(1.200 / rig.period - 1e-6)


def test_mode_3_blended_segments_are_not_slowed_by_an_assumed_stop(rig):
    """Unlike Mode 1 the lookahead knows the next move, so no stop is assumed after each: TM20
    segments of 1000 counts (50 counts/ms; a stop at Ixx17 = 0.2 would take 250 ms) keep their
    20 ms after the first (whose ramp from rest is limited)."""
    _lookahead_setup(rig, 40, "I116=1000", "I117=0.2")
    _run(rig, ["LINEAR INC TA10 TS0 TM20"] + ["X1"] * 6)
    starts = sorted(k for k, _, _ in rig.events("move_start"))
    for a, b in zip(starts[1:], starts[2:], strict=False):
        assert abs((b - a) - rig.ms_cycles(20)) <= 1


def _calculated_at_first_rti(rig):
    ks = [k for k, _, _ in rig.events("line_calculated")]
    return sum(1 for k in ks if k == ks[0])


def test_tsrm_p181_calculation_runs_isx20_segments_ahead(rig):
    """Isx20 = 45 segments of 10 ms: 450 ms ahead. From rest the first RTI calculates TM100
    moves until they cover it (the mode line and five moves) instead of segmented LINEAR's
    two from rest."""
    _lookahead_setup(rig, 45, "I117=1000")
    rig.c.load_lines(1, ["LINEAR ABS TA10 TS0 TM100"] + [f"X{i / 100}" for i in range(1, 20)])
    rig.ok("R")
    rig.run_for(0.01)
    assert _calculated_at_first_rti(rig) == 6


def test_segmented_without_the_lookahead_calculates_one_move_ahead(rig):
    _lookahead_setup(rig, 50, "I117=1000", lookahead=False)
    rig.c.load_lines(1, ["LINEAR ABS TA10 TS0 TM100"] + [f"X{i / 100}" for i in range(1, 20)])
    rig.ok("R")
    rig.run_for(0.01)
    assert _calculated_at_first_rti(rig) == 3


def test_mode_3_the_stop_is_decided_its_ixx17_ramp_ahead_so_a_late_line_no_longer_blends(rig):
    """TM1000 TA100 X10 then X20 (10 counts/ms) at Ixx17 = 0.05: move 2 blends in with TA 100
    but its stop needs 200 ms, so its deceleration is decided 100 ms before its end (t0+2000
    ms, t0 = line 1's start) instead of 50 ms (t0+2050). X30 arriving at t0+2025 ms is too
    late: move 2 stops, its end 100 ms after its programmed end, t0+2200 ms."""
    _lookahead_setup(rig, 10, "I116=1000", "I117=0.05")
    rig.c.load_lines(1, ["LINEAR ABS TA100 TS0 TM1000 X10", "X20"])
    rig.ok("R")
    rig.run_for(0.01)
    k0 = {f["n"]: k for k, _, f in rig.events("move_start")}[1]
    rig.c.env.run(until=k0 * rig.period + 2.025)
    rig.c.load_lines(1, ["X30"])
    rig.run_until_idle()
    end = {f["n"]: k for k, _, f in rig.events("move_end")}
    assert abs(end[2] - k0 - rig.ms_cycles(2200)) <= 1
