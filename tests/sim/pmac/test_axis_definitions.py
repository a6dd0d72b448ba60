"""Axis definitions as the SRM writes them (TSRM p268-270; TUM p258; PSRM p179-180; spec §12.5),
``UNDEFINE`` / ``UNDEFINE ALL``, the ``#n->`` query, and ``FRAX``/``INC``/``ABS`` axis lists in
programs (move times asserted on the event log, in servo cycles)."""

from __future__ import annotations

import math

import pytest


@pytest.mark.parametrize("definition", [
    "1000X", "-29.1X+100000Y", "2000Z-6000", "3333.333Z-666.667", "5000A", "8660X-5000Y",
    "X", "-X", "0.5U+0.5V+W", "I",
])
def test_tsrm_p268_definition_is_stored_and_reported_in_the_cards_form(rig, definition):
    rig.ok(f"&1 #6->{definition}")
    assert rig.ok("&1 #6->") == definition


def test_tsrm_p268_blanks_lower_case_and_unit_scale_are_normalised(rig):
    rig.ok("&1 #2-> 1x + 2.50y")
    assert rig.ok("&1#2->") == "X+2.5Y"


@pytest.mark.parametrize(("text", "column"), [
    ("#8->1000A+Y", 11), ("#8->X+U", 7), ("#8->X-X", 7), ("#8->5000", 9), ("#8->X+Y+Z+X", 11),
    ("#8->X Y", 7),
])
def test_tsrm_p268_invalid_combinations_are_err003_and_change_nothing(rig, text, column):
    rig.ok("&1 #8->100Z")
    reply = rig.cmd(f"&1 {text}")
    assert reply.error == "ERR003"
    assert rig.c._terminal.detail[1].endswith(f"(column {column + 3})")
    assert rig.ok("&1 #8->") == "100Z"


def test_tsrm_p269_a_motor_defined_in_another_cs_is_refused(rig):
    rig.ok("&1 #1->X")
    assert rig.cmd("&2 #1->Y").error == "ERR003"
    assert rig.ok("&2 #1->") == "0" and rig.ok("&1 #1->") == "X"


def test_tsrm_p269_undefine_clears_the_addressed_cs_and_undefine_all_every_cs(rig):
    rig.ok("&1 #1->X #2->Y")
    rig.ok("&2 #3->Z #4->A")
    rig.ok("&2 UNDEFINE")
    assert [rig.ok(f"&2 #{n}->") for n in (3, 4)] == ["0", "0"]
    assert [rig.ok(f"&1 #{n}->") for n in (1, 2)] == ["X", "Y"]
    rig.ok("&2 #3->Z")
    rig.ok("UNDEFINE ALL")
    assert [rig.ok(f"&{c} #{n}->") for c, n in ((1, 1), (1, 2), (2, 3))] == ["0"] * 3


def test_tsrm_p268_motor_position_is_the_sum_of_its_terms(rig):
    """``#1->8660X-5000Y`` / ``#2->5000X+8660Y`` (a 30° rotation): after ``X1 Y2`` motor 1 is
    at 8660·1 - 5000·2 counts and motor 2 at 5000·1 + 8660·2."""
    rig.ok("&1 #1->8660X-5000Y #2->5000X+8660Y")
    rig.ok("#1$ #2$")
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM100 TA10 TS0 X1 Y2"])
    rig.ok("&1 R")
    rig.run_until_idle()
    assert float(rig.ok("#1P")) == pytest.approx(8660 - 10000)
    assert float(rig.ok("#2P")) == pytest.approx(5000 + 17320)


def _move_cycles(rig, lines: list[str]) -> int:
    rig.ok("&1 #1->X #2->Y")  # 1 count per unit: far from the Ixx16/Ixx17 limits
    rig.rotary_setup()
    rig.c.load_lines(1, lines)
    rig.ok("&1 R")
    rig.run_until_idle()
    return rig.by_n("move_end")[len(lines)] - rig.by_n("move_start")[len(lines)]


@pytest.mark.parametrize(("frax", "units"), [("FRAX(X,Y)", 5), ("FRAX(X)", 3), ("FRAX(Y)", 4),
                                             ("FRAX", 5)])
def test_tsrm_frax_picks_the_vector_feedrate_axes(rig, frax, units):
    """``X3 Y4 F50``: 5 units over X and Y, 3 over X alone, at 50 units/s (+ TA from rest)."""
    cycles = _move_cycles(rig, [frax, "TA20 TS0 X3 Y4 F50"])
    assert cycles == math.ceil(rig.ms_cycles(units / 50 * 1000 + 20) - 1e-6)


def test_tsrm_inc_and_abs_with_axis_lists_in_a_program(rig):
    """``INC(X)`` makes X incremental only; ``ABS(X)`` back: X1 X1 INC(X) X1 ABS(X) X1 -> X=1."""
    rig.ok("&1 #1->1000X")
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM50 TA10 TS0 X1", "INC(X) X2 Y5", "ABS(X,Y) X1"])
    rig.ok("&1 R")
    rig.run_until_idle()
    assert float(rig.ok("#1P")) == pytest.approx(1000)
    rig.c.load_lines(1, ["INC(X) X2"])
    rig.run_until_idle()
    assert float(rig.ok("#1P")) == pytest.approx(3000)
