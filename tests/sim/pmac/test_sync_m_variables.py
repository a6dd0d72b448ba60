"""Plain versus synchronous M-variable assignment (seed 001, TUM p249-250, TSRM p446).

TUM p250: a synchronous write is performed where blending into the next move begins, the
queue is checked every RTI (I8+1 servo cycles), and with Isx13 > 0 it runs at the start of the
first Isx13 segment after blending begins. Times here are servo cycles.
"""

from __future__ import annotations

import math

import pytest


def _load(rig, lines, setup=()):
    rig.rotary_setup()
    for s in setup:
        rig.ok(s)
    rig.ok("OPEN ROT")
    for line in lines:
        rig.ok(line)
    rig.ok("CLOSE")
    rig.ok("R")
    rig.run_until_idle()


def _first(rig, type_, **match):
    for k, _t, f in rig.events(type_):
        if all(f.get(a) == b for a, b in match.items()):
            return k, f
    raise AssertionError(f"no {type_} {match}")


def _rti_at_or_after(k: int, rti: int) -> int:
    return -(-k // rti) * rti


def test_plain_m1_fires_at_calculation_at_the_start_of_the_move_to_x10(rig):
    """Seed 001: ``X10 / M1=1 / X20`` — calculating ahead, PMAC works through ``M1=1`` at the
    beginning of the move to X10, so the output turns on then, not at X10."""
    _load(rig, ["X10 TM500 TA100 TS0", "M1=1", "X20"])
    k_start1, _ = _first(rig, "move_start", n=1)
    k_m, f = _first(rig, "mvar", name="M1")
    assert (f["value"], f["sync"]) == (1.0, False)
    assert k_m == k_start1
    assert k_start1 % 3 == 0  # calculated and started at an RTI
    assert [x for x in rig.events("mvar")] == [(k_m, "mvar", f)]


def test_tum_p250_synchronous_m1_lands_on_the_first_rti_at_or_after_the_blend_into_x20(rig):
    """Seed 001 / TUM p250: ``X10 / M1==1 / X20`` — encountered at the start of the move to
    X10, performed where blending into X20 begins (Ta/2 before the X10 point), but only when
    the queue is next checked: the first RTI (every I8+1 = 3 cycles) at or after that."""
    _load(rig, ["X10 TM500 TA100 TS0", "M1==1", "X20"])
    k_start1, _ = _first(rig, "move_start", n=1)
    k_start3, _ = _first(rig, "move_start", n=3)
    k_end1, _ = _first(rig, "move_end", n=1)
    k_m, f = _first(rig, "mvar", name="M1")
    assert (f["value"], f["sync"]) == (1.0, True)
    assert k_start3 == k_end1
    # Blend starts Ta/2 = 50 ms before the programmed X10 point, which is TM + Ta/2 after start.
    assert k_start3 - k_start1 == -(-round(rig.ms_cycles(500) * 1e6) // 1_000_000)
    assert k_start3 % 3 != 0  # the blend starts between two RTIs ...
    assert k_m == _rti_at_or_after(k_start3, 3)  # ... so the write waits for the next one
    assert k_m % 3 == 0 and 0 < k_m - k_start3 < 3


def test_tum_p250_with_i8_0_the_write_lands_on_the_blend_start_cycle_itself(rig):
    """I8 = 0: an RTI every servo cycle, so the write is on the cycle blending begins, after
    the previous move's end and before the next move's start."""
    _load(rig, ["X10 TM500 TA100 TS0", "M1==1", "X20"], setup=["I8=0"])
    k_start3, _ = _first(rig, "move_start", n=3)
    k_m, _ = _first(rig, "mvar", name="M1")
    assert k_m == k_start3
    order = [(t, f.get("n")) for k, t, f in rig.events() if k == k_m and t != "line_calculated"]
    assert order == [("move_end", 1), ("mvar", None), ("move_start", 3)]


def test_tum_p250_the_smaller_i8_the_tighter_the_timing(make_rig):
    """TUM p250: "the smaller I8 is ... the tighter the timing control": the same program with
    I8 = 2, 5, 9 puts the write on that RTI grid, never more than I8 cycles late."""
    for i8 in (2, 5, 9):
        rig = make_rig()
        _load(rig, ["X10 TM500 TA100 TS0", "M1==1", "X20"], setup=[f"I8={i8}"])
        k_start3, _ = _first(rig, "move_start", n=3)
        k_m, _ = _first(rig, "mvar", name="M1")
        assert k_m == _rti_at_or_after(k_start3, i8 + 1), i8
        assert 0 <= k_m - k_start3 <= i8


def test_tum_p250_the_write_on_an_rti_comes_before_planning_at_that_rti(rig):
    """``[INF]`` the queue is served before move planning in the RTI: the write and the
    ``line_calculated`` of the planning pass asked for by the move's start share that RTI,
    write first."""
    _load(rig, ["X10 TM500 TA100 TS0", "M1==1", "X20", "X30", "X40"])
    k_m, _ = _first(rig, "mvar", name="M1")
    same = [t for k, t, _ in rig.events() if k == k_m]
    assert "line_calculated" in same
    assert same.index("mvar") < same.index("line_calculated")


def test_tum_p250_segmented_write_waits_for_the_first_isx13_segment_after_blending(make_rig):
    """TUM p250: with Isx13 > 0 the write runs at the start of the first Isx13 segment after
    the start of blending into the move; the segments of a sequence start when it starts
    from rest ``[INF]``, every Isx13 ms; then the next RTI."""
    rig = make_rig()
    _load(rig, ["X10 TM500 TA100 TS0", "M1==1", "X20"], setup=["I5113=10"])
    k_start1, _ = _first(rig, "move_start", n=1)
    k_start3, _ = _first(rig, "move_start", n=3)
    k_m, _ = _first(rig, "mvar", name="M1")
    seg = 0.010
    t0, t_blend = k_start1 * rig.period, k_start3 * rig.period
    t_seg = t0 + math.ceil((t_blend - t0) / seg - 1e-9) * seg
    k_seg = math.ceil(t_seg / rig.period - 1e-6)
    assert k_seg > k_start3 + 3  # the segment boundary is well after the blend start here
    assert k_m == _rti_at_or_after(k_seg, 3)
    # the same program without segmentation writes at the RTI after the blend start
    plain = make_rig()
    _load(plain, ["X10 TM500 TA100 TS0", "M1==1", "X20"])
    k_plain, _ = _first(plain, "mvar", name="M1")
    assert k_plain == _rti_at_or_after(_first(plain, "move_start", n=3)[0], 3) < k_m


def test_synchronous_assignments_left_after_the_last_move_are_not_executed(rig):
    """TUM p250: synchronous assignments after the last move are not performed."""
    _load(rig, ["X10 TM100 TA10 TS0", "M2==1"])
    assert rig.events("mvar") == []
    assert rig.c.coord(1)["program"]["state"] == "waiting"


def test_synchronous_assignment_before_a_dwell_fires_at_the_first_rti_of_the_dwell(rig):
    """TUM p250: written at the start of the next move *or dwell*; ``DWELL0`` flushes. The
    dwell starts when the move has stopped; the write at the first RTI at or after that."""
    _load(rig, ["X10 TM100 TA10 TS0", "M3==7", "DWELL0"])
    k_dwell, _ = _first(rig, "move_start", n=3)
    k_m, f = _first(rig, "mvar", name="M3")
    assert (k_m, f["value"], f["sync"]) == (_rti_at_or_after(k_dwell, 3), 7.0, True)


def test_bitwise_synchronous_forms(rig):
    """``&=``, ``|=``, ``^=`` combine with the M-variable's value when the write happens."""
    rig.ok("M5=6")
    _load(rig, ["X1 TM50 TA10 TS0", "M5&=3", "X2", "M5|=8", "X3", "M5^=1", "X4"])
    values = [f["value"] for _, _, f in rig.events("mvar") if f["name"] == "M5"]
    assert values == [6.0, 2.0, 10.0, 11.0]


def test_bitwise_form_reads_the_variable_when_the_write_is_performed_not_at_calculation(rig):
    """PUM p160 (``M50&=$AA`` versus ``M50==M50&$AA``): the &= form reads M at the write, so a
    change made between calculation and the write is kept; ``==`` used the value read at
    calculation."""
    rig.rotary_setup()
    rig.c.load_lines(1, ["X10 TM500 TA100 TS0", "M5|=1 M6==M6|1", "X20"])
    rig.ok("R")
    rig.run_for(0.2)  # both calculated (two moves ahead), neither written yet
    assert rig.events("mvar") == []
    rig.ok("M5=4 M6=4")
    rig.run_until_idle()
    sync = {f["name"]: f["value"] for _, _, f in rig.events("mvar") if f["sync"]}
    assert sync == {"M5": 5.0, "M6": 1.0}


def test_tum_p250_mflush_removes_a_stale_write_and_the_next_streamed_write_fires(rig):
    """TUM p250 / issue 16: the program ran out of lines with ``M1==1`` queued behind the
    last move; ``MFLUSH`` (addressed CS, acknowledged with nothing but the handshake) removes
    it, so when the host streams more lines M1 is never written but the new ``M2==1`` is, at
    the first RTI at or after the start of blending into the move after it."""
    rig.rotary_setup()
    rig.c.load_lines(1, ["X10 TM100 TA10 TS0", "M1==1"])
    rig.ok("R")
    rig.run_for(0.3)
    assert rig.c.coord(1)["program"]["state"] == "waiting"
    before = len(rig.c.log.read(0).events)
    assert rig.ok("&1 MFLUSH") == ""
    mflush_events = [t for _, t, _ in rig.events()][before:]
    assert set(mflush_events) <= {"terminal_reply"}  # nothing else changes
    rig.c.load_lines(1, ["X20", "M2==1", "X30"])
    rig.run_until_idle()
    writes = [(k, f["name"]) for k, _, f in rig.events("mvar")]
    k_start5, _ = _first(rig, "move_start", n=5)
    assert writes == [(_rti_at_or_after(k_start5, 3), "M2")]


def test_mflush_acts_on_the_addressed_cs_only(rig):
    """``[INF]`` MFLUSH is coordinate-system specific: CS 2's leftover write survives an
    MFLUSH addressed to CS 1 and fires at CS 2's next move."""
    rig.rotary_setup(cs=2)
    rig.c.load_lines(2, ["X10 TM100 TA10 TS0", "M7==1"])
    rig.ok("&2 R")
    rig.run_for(0.3)
    rig.ok("&1 MFLUSH")
    rig.c.load_lines(2, ["X20"])
    rig.run_until_idle()
    assert [f["name"] for _, _, f in rig.events("mvar")] == ["M7"]


@pytest.mark.parametrize("command", ["A", "\x0b"])
def test_a_or_ctrl_k_between_the_blend_start_and_its_rti_discards_the_write(make_rig, command):
    """TUM p319: ``A`` and CTRL-K discard queued synchronous writes — also one whose move has
    begun but whose RTI has not come yet (I8 = 29: an RTI every 30 cycles, ≈ 13 ms)."""
    rig = make_rig()
    rig.rotary_setup()
    rig.ok("I8=29")
    rig.c.load_lines(1, ["X10 TM480 TA100 TS0", "M1==1", "X20"])
    rig.ok("R")
    env = rig.c.env
    while not any(f.get("n") == 3 for _, _, f in rig.events("move_start")):
        env.step()
    k_start3, _ = _first(rig, "move_start", n=3)
    assert k_start3 % 30 < 20  # the write waits at least 10 cycles for its RTI
    a = rig.cmd(command)
    assert a.error is None
    assert rig.cyc(a.t_done) < _rti_at_or_after(k_start3, 30)
    rig.run_until_idle()
    assert rig.events("mvar") == []


def test_mflush_while_running_removes_writes_calculated_with_moves_not_yet_started(rig):
    """``[INF]`` MFLUSH empties the whole queue: ``M1==1`` calculated (two moves ahead) with
    the move to X20 is removed before that move starts, and the program runs on."""
    rig.rotary_setup()
    rig.c.load_lines(1, ["X10 TM500 TA100 TS0", "M1==1", "X20"])
    rig.ok("R")
    rig.run_for(0.2)
    assert [f["n"] for _, _, f in rig.events("line_calculated")] == [1, 2, 3]
    rig.ok("MFLUSH")
    rig.run_until_idle()
    assert rig.events("mvar") == []
    assert [f["n"] for _, _, f in rig.events("move_start")] == [1, 3]
    assert rig.c.positions(1)["X"] == 20.0


def test_mflush_removes_the_write_waiting_with_an_open_spline_point(rig):
    """``[INF]`` a synchronous write before the last SPLINE1 point waits with that point
    until the series is ended; MFLUSH removes it there too."""
    rig.rotary_setup()
    rig.c.load_lines(1, ["ABS SPLINE1 TM100 X10", "X20", "M1==1 X30"])
    rig.ok("R")
    rig.run_for(0.05)
    rig.ok("MFLUSH")
    rig.run_until_idle()
    assert rig.events("mvar") == []
    assert rig.c.positions(1)["X"] == 30.0
