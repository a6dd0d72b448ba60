"""Plain versus synchronous M-variable assignment (seed 001, TUM p249-250, TSRM p446)."""

from __future__ import annotations


def _load(rig, lines):
    rig.rotary_setup()
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


def test_synchronous_m1_fires_at_the_start_of_the_blend_into_x20(rig):
    """Seed 001: ``X10 / M1==1 / X20`` — encountered at the start of the move to X10 but
    performed at the start of blending into the move to X20 (Ta/2 before the X10 point)."""
    _load(rig, ["X10 TM500 TA100 TS0", "M1==1", "X20"])
    k_start1, _ = _first(rig, "move_start", n=1)
    k_start3, _ = _first(rig, "move_start", n=3)
    k_end1, _ = _first(rig, "move_end", n=1)
    k_m, f = _first(rig, "mvar", name="M1")
    assert (f["value"], f["sync"]) == (1.0, True)
    assert k_m == k_start3 == k_end1
    # Blend starts Ta/2 = 50 ms before the programmed X10 point, which is TM + Ta/2 after start.
    assert k_start3 - k_start1 == -(-round(rig.ms_cycles(500) * 1e6) // 1_000_000)
    # order within the cycle: previous move ends, the sync write, the next move starts
    order = [(t, f.get("n")) for k, t, f in rig.events() if k == k_m and t != "line_calculated"]
    assert order == [("move_end", 1), ("mvar", None), ("move_start", 3)]


def test_synchronous_assignments_left_after_the_last_move_are_not_executed(rig):
    """TUM p250: synchronous assignments after the last move are not performed."""
    _load(rig, ["X10 TM100 TA10 TS0", "M2==1"])
    assert rig.events("mvar") == []
    assert rig.c.coord(1)["program"]["state"] == "waiting"


def test_synchronous_assignment_before_a_dwell_fires_at_the_dwell(rig):
    """TUM p250: written at the start of the next move *or dwell*; ``DWELL0`` flushes."""
    _load(rig, ["X10 TM100 TA10 TS0", "M3==7", "DWELL0"])
    k_dwell, _ = _first(rig, "move_start", n=3)
    k_m, f = _first(rig, "mvar", name="M3")
    assert (k_m, f["value"], f["sync"]) == (k_dwell, 7.0, True)


def test_bitwise_synchronous_forms(rig):
    """``&=``, ``|=``, ``^=`` combine with the M-variable's value when the write happens."""
    rig.ok("M5=6")
    _load(rig, ["X1 TM50 TA10 TS0", "M5&=3", "X2", "M5|=8", "X3", "M5^=1", "X4"])
    values = [f["value"] for _, _, f in rig.events("mvar") if f["name"] == "M5"]
    assert values == [6.0, 2.0, 10.0, 11.0]
