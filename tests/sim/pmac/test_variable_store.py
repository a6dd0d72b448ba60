"""The PMAC variable store as a host sees it: P global, Q one bank per coordinate system,
plain M-variables integer (TSRM p23; TUM p243–246; spec pmac.md §3, §9.10)."""

from __future__ import annotations

import pytest


@pytest.mark.parametrize(
    ("assign", "answer"),
    [
        ("M1=10*2/3", "7"),  # the manual's example: an integer target rounds (spec §9.10)
        ("M1=-10*2/3", "-7"),
        ("M1=2.4", "2"),
        ("M1=-2.4", "-2"),
        ("M1=-2.5", "-3"),  # [INF] half away from zero
        ("M1=2.5", "3"),
        ("M1=-1", "-1"),
        ("M1=-0.2", "0"),
    ],
)
def test_a_plain_m_variable_holds_the_rounded_integer(rig, assign, answer):
    rig.ok(assign)
    assert rig.ok("M1").strip() == answer


def test_p_keeps_fractions_and_reports_them_without_an_exponent(rig):
    rig.ok("P1=10*2/3 P2=0.0000001 P3=-1.25")
    assert rig.ok("P1..3").split() == ["6.666666667", "0.0000001", "-1.25"]


def test_q_variables_have_one_bank_per_coordinate_system(rig):
    rig.ok("&2 Q3=5")
    rig.ok("&1 Q3=7")
    assert rig.ok("&2 Q3").strip() == "5"
    assert rig.ok("&1 Q3").strip() == "7"
    assert rig.c.get_variable("&2Q3") == 5.0 and rig.c.get_variable("Q3") == 7.0
    rig.c.set_variable("&16Q3", 9)
    assert rig.ok("&16 Q3").strip() == "9" and rig.ok("&2 Q3").strip() == "5"


@pytest.mark.parametrize("name", ["I0", "I8191", "P8191", "&16Q8191", "M8191"])
def test_the_ends_of_each_variable_set_exist(rig, name):
    rig.c.set_variable(name, 1)
    assert rig.c.get_variable(name) == 1.0


@pytest.mark.parametrize(
    "name", ["I8192", "I9999", "P8192", "&17Q1", "&0Q1", "X1", "I", "&Q1", "&2"]
)
def test_names_outside_the_sets_are_not_found(rig, name):
    with pytest.raises(Exception) as exc:
        rig.c.get_variable(name)
    assert "no such variable" in str(exc.value)


def test_variables_start_at_0_and_plain_m_variables_too(rig):
    assert [rig.ok(v).strip() for v in ("P7", "&3Q7", "M100")] == ["0", "0", "0"]


def test_number_0_is_a_variable_like_the_others(rig):
    rig.ok("P0=5 I0=3")
    rig.ok("&1 Q0=4")
    assert [rig.ok(v).strip() for v in ("P0", "I0", "Q0")] == ["5", "3", "4"]


def test_an_indirect_number_outside_0_to_8191_reads_0_and_writes_nothing(rig):
    """[INF] (variables.py): an I/P/Q/M number computed out of range reads 0 inside an
    expression; as the target of an on-line assignment it is ERR003 (spec §12.4), and
    nothing is written either way."""
    rig.ok("P8191=6 P0=7 P1=-1 P2=8192")
    assert rig.cmd("P(P1)=9").error == "ERR003"
    assert rig.cmd("P(P2)=9").error == "ERR003"
    rig.ok("P3=P(P1)+P(P2)")
    assert rig.ok("P8191").strip() == "6" and rig.ok("P0").strip() == "7"
    assert rig.ok("P3").strip() == "0"


def test_i9_1_reports_whole_statements_with_addresses_in_decimal(rig):
    """TSRM p42 table: I9=1 is long form with decimal address I-variables."""
    rig.ok("I9=1")
    assert rig.ok("I124").strip() == "I124=262145"  # $40001
    assert rig.ok("I130").strip() == "I130=2000"


def test_i_n_star_restores_a_default_that_the_next_run_uses(rig):
    """Isx89 (default feedrate) of 10 units/s, then ``I5189=*`` (1000): the first run of a
    10-unit move takes over 1 s, the run after the reset to the default only its
    acceleration time (Isx87 / Isx88, about 0.2 s)."""
    rig.ok("OPEN PROG 1 CLEAR")
    rig.ok("LINEAR INC X10")
    rig.ok("CLOSE")
    rig.ok("I5189=10")
    rig.ok("&1 B1 R")
    rig.run_until_idle()
    rig.ok("I5189=*")
    rig.ok("&1 B1 R")
    rig.run_until_idle()
    starts = [k for k, _, _ in rig.events("move_start")]
    ends = [k for k, _, _ in rig.events("move_end")]
    slow, fast = (e - s for s, e in zip(starts, ends, strict=True))
    assert slow > rig.ms_cycles(900) and fast < rig.ms_cycles(300)


def test_i15_chooses_degrees_or_radians_for_the_trig_functions(rig):
    """TUM p248: I15 = 0 degrees (factory), 1 radians."""
    rig.ok("P1=SIN(90)")
    rig.ok("I15=1")
    rig.ok("P2=SIN(90)")
    assert rig.ok("P1").strip() == "1"
    assert float(rig.ok("P2")) == pytest.approx(0.8939966636)
