"""``PSET{axis}{data}``: new present positions without motion, a lookahead break (TSRM p31,
TUM p341, PSRM p340; spec §11.4). Times in servo cycles; RTIs every 3 (I8 = 2)."""

from __future__ import annotations

import math


def _run(rig, lines, setup=()):
    rig.rotary_setup()
    for s in setup:
        rig.ok(s)
    rig.c.load_lines(1, lines)
    rig.ok("R")
    rig.run_until_idle()


def _at(rig, type_, **match):
    out = [k for k, _, f in rig.events(type_) if all(f.get(a) == b for a, b in match.items())]
    assert len(out) == 1, (type_, match, out)
    return out[0]


def test_tsrm_p31_pset_sets_the_present_position_without_motion(rig):
    """``PSET X0`` after a move to X10: X is 0 from then on, nothing moved (no move for the
    PSET line), and the ``pset`` event names the new position."""
    _run(rig, ["TM100 TA10 TS0 X10", "PSET X0"])
    assert rig.c.positions(1)["X"] == 0.0
    assert [f["n"] for _, _, f in rig.events("move_start")] == [1]
    (_k, _t, f), = rig.events("pset")
    assert f == {"cs": 1, "n": 2, "positions": {"X": 0.0}}
    assert _at(rig, "pset", n=2) == _at(rig, "move_end", n=1)  # at rest, at once
    assert rig.c.coord(1)["program"]["state"] == "waiting"


def test_pset_changes_the_axis_offset_the_motor_does_not_move(rig):
    """PSRM p180: PSET changes the offset between axis zero and motor zero. Motor 1 on X keeps
    its 10 counts through ``PSET X0``; the next ``X5`` takes it 5 counts further, to 15."""
    rig.ok("&1 #1->X")
    _run(rig, ["TM100 TA10 TS0 X10", "PSET X0"])
    assert rig.c.motor_position(1) == 10.0
    assert rig.c.positions(1)["X"] == 0.0
    rig.c.load_lines(1, ["X5"])
    rig.run_until_idle()
    assert rig.c.positions(1)["X"] == 5.0
    assert rig.c.motor_position(1) == 15.0


def test_tum_p341_pset_breaks_blending_next_move_calculated_only_after_it_ran(rig):
    """TUM p341: the move before PSET is not blended into the move after; the move after is
    not calculated until the move before has finished and PSET executed. Control: without
    PSET the two moves blend (the second starts where the first's blend begins)."""
    _run(rig, ["TM100 TA50 TS0 X10", "PSET X0", "X5"])
    k_start1 = _at(rig, "move_start", n=1)
    k_end1 = _at(rig, "move_end", n=1)
    k_pset = _at(rig, "pset", n=2)
    k_calc3 = _at(rig, "line_calculated", n=3)
    k_start3 = _at(rig, "move_start", n=3)
    # the first move ran to a stop: TM + Ta/2 ramp-in ... + Ta/2 ramp-out = TM + Ta
    assert k_end1 == k_start1 + math.ceil(rig.ms_cycles(150) - 1e-6)
    assert k_pset == k_end1
    # calculated at the first RTI strictly after PSET ran (I11 = 0: starts at once)
    assert k_calc3 == (k_pset // 3 + 1) * 3
    assert k_start3 == k_calc3
    assert rig.c.positions(1)["X"] == 5.0

    plain = type(rig)()
    _run(plain, ["TM100 TA50 TS0 X10", "X5"])
    assert _at(plain, "move_start", n=2) == _at(plain, "move_end", n=1)
    assert _at(plain, "line_calculated", n=2) < _at(plain, "move_end", n=1)


def test_tum_p341_after_pset_the_i11_calculation_delay_applies(rig):
    """PSRM I11 / TUM p341: after the break the next move starts I11 ms after PSET ran (on a
    servo cycle), not at the RTI that calculates it."""
    _run(rig, ["TM100 TA50 TS0 X10", "PSET X0", "X5"], setup=["I11=20"])
    k_pset = _at(rig, "pset", n=2)
    k_start3 = _at(rig, "move_start", n=3)
    t_due = (k_pset * rig.period) + 0.020
    assert k_start3 == math.ceil(t_due / rig.period - 1e-6)
    assert _at(rig, "line_calculated", n=3) < k_start3


def test_pset_values_are_absolute_even_in_inc_mode(rig):
    """``[INF]`` PSET "assigns new values": INC does not apply to it."""
    _run(rig, ["INC TM50 TA10 TS0 X10", "PSET X3 Y-2"])
    pos = rig.c.positions(1)
    assert (pos["X"], pos["Y"]) == (3.0, -2.0)


def test_synchronous_write_before_pset_goes_with_the_next_move(rig):
    """TUM p250: synchronous writes are performed at the start of the next move or DWELL;
    PSET is neither ``[INF]``, so ``M1==1`` before it lands at the first RTI at or after the
    start of the move after it."""
    _run(rig, ["TM100 TA50 TS0 X10", "M1==1", "PSET X0", "X5"])
    k_start4 = _at(rig, "move_start", n=4)
    assert [(k, f["name"]) for k, _, f in rig.events("mvar")] == [(-(-k_start4 // 3) * 3, "M1")]


def test_pset_words_one_per_value(rig):
    """Seed 000 "each value in a program takes one word" ``[INF]``: ``PSET X0 Y0`` two."""
    rig.rotary_setup()
    rig.ok("OPEN ROT")
    rig.ok("PSET X0 Y0")
    rig.ok("CLOSE")
    (_, _, f), = rig.events("line_loaded")
    assert (f["text"], f["words"]) == ("PSET X0 Y0", 2)


def test_pset_without_axis_or_value_is_err003_and_nothing_is_stored(rig):
    """Bad input: ``PSET`` with no ``{axis}{data}``, or an axis without a value, answers the
    card's ERR003 with the column; the rotary buffer and the log are unchanged."""
    rig.rotary_setup()
    rig.ok("OPEN ROT")
    before = len(rig.c.log.read(0).events)
    for text, col in (("PSET", 5), ("PSET X", 7), ("X1 PSET", 8), ("PSET 5", 6)):
        r = rig.cmd(text)
        assert r.error == "ERR003", text
        kind, message = r.detail
        assert kind == "parse_error" and f"column {col}" in message, (text, message)
        assert "PSET" in message
    types = [t for _, t, _ in rig.events()][before:]
    assert set(types) <= {"terminal_reply"}
    assert rig.c.rotary(1)["used_words"] == 0
    assert rig.c.rotary(1)["lines_ahead"] == 0
    rig.ok("CLOSE")


def test_pset_with_no_buffer_open_is_err005(rig):
    """A program statement sent on-line with no buffer open answers ERR005 (TUM p46)."""
    assert rig.cmd("PSET X0").error == "ERR005"
    assert rig.events("pset") == []


def test_pset_in_a_fixed_program_runs_to_its_end_and_is_listed(rig):
    """A fixed program (``OPEN PROG``, ``B1 R``) with PSET between two moves: the program
    ends ``stopped`` at X = -5 (10 → PSET 0 → INC X-5), two moves, one ``pset``."""
    rig.ok("OPEN PROG 1 CLEAR")
    for line in ("TM50 TA10 TS0 X10", "PSET X0", "INC X-5"):
        rig.ok(line)
    rig.ok("CLOSE")
    assert rig.ok("LIST PROG 1").split("\r")[1] == "PSETX0"  # the card's compact listing
    rig.ok("&1 B1 R")
    rig.run_until_idle()
    assert rig.c.positions(1)["X"] == -5.0
    assert len(rig.events("move_start")) == 2 and len(rig.events("pset")) == 1
    assert rig.c.coord(1)["program"]["state"] == "stopped"


def test_pset_first_after_r_runs_at_the_calculating_rti_and_i11_comes_once_after_it(rig):
    """``[INF]`` a PSET calculated with the CS at rest runs at that RTI (I11 is the delay
    before a *move*); the move after it starts I11 ms after the PSET."""
    _run(rig, ["PSET X100", "TM50 TA10 TS0 X105"], setup=["I11=20"])
    k_pset = _at(rig, "pset", n=1)
    assert k_pset == _at(rig, "line_calculated", n=1) and k_pset % 3 == 0
    k_start2 = _at(rig, "move_start", n=2)
    assert k_start2 == math.ceil((k_pset * rig.period + 0.020) / rig.period - 1e-6)
    assert rig.c.positions(1)["X"] == 105.0
