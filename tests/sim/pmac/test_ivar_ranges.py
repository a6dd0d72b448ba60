"""I-variable value rules: limited ranges roll over (TUM p243), I41 locks sets (TSRM p57).

Over the terminal, from PLC and motion programs, over REST and from config: every write
of an I-variable goes through the same rule, so each path is pinned once.
"""

from __future__ import annotations

import pytest
from motionsim.sim.pmac.card.factory import FACTORY, default_i
from motionsim.sim.pmac.card.ivar_ranges import RANGES, roll_over


def query(rig, name: str) -> str:
    """The reply to a query as a decimal text: address-type variables answer ``$hex`` (I9=2),
    and with I9 bit 0 set the whole statement ``I9=3``."""
    text = rig.ok(name).strip().split("=")[-1]
    return str(int(text[1:], 16)) if text.startswith("$") else text


#: The SRM's ``Range:`` of each limited-range integer I-variable (name, lo, hi, page).
MANUAL_RANGES = [
    ("I3", 0, 3, "TSRM p37"), ("I4", 0, 3, "TSRM p38"), ("I5", 0, 3, "TSRM p39"),
    ("I6", 0, 3, "PSRM p25"), ("I9", 0, 3, "TSRM p42"), ("I40", 0, 65_535, "TSRM p57"),
    ("I41", 0, 15, "TSRM p57"), ("I42", 0, 1, "TSRM p58"), ("I43", 0, 3, "TSRM p58"),
    ("I59", 0, 3, "TSRM p65"), ("I60", 0, 15, "TSRM p65"), ("I63", 0, 1, "TSRM p67"),
    ("I64", 0, 1, "TSRM p67"), ("I67", 0, 0x3FFFF, "TSRM p68"), ("I5000", 0, 3, "TSRM p170"),
    ("I180", 0, 7, "TSRM p136"), ("I3280", 0, 7, "TSRM p136"),  # Ixx80, motors 1 and 32
    ("I5113", 0, 255, "TSRM p177"), ("I6613", 0, 255, "TSRM p177"),  # Isx13, CS 1 and 16
    ("I5121", 0, 15, "TSRM p181"), ("I6621", 0, 15, "TSRM p181"),  # Isx21
    ("I5150", 0, 1, "TSRM p181"), ("I6650", 0, 1, "TSRM p181"),  # Isx50
    ("I5192", 0, 1, "TSRM p184-190"), ("I6692", 0, 1, "TSRM p184-190"),  # Isx92
]


@pytest.mark.parametrize(("name", "lo", "hi", "page"), MANUAL_RANGES)
def test_one_past_each_end_of_a_manual_range_wraps_to_the_other_end(rig, name, lo, hi, page):
    rig.ok(f"{name}={hi + 1}")
    assert query(rig, name) == str(lo)
    rig.ok(f"{name}={lo - 1}")
    assert query(rig, name) == str(hi)
    rig.ok(f"{name}={hi}")
    assert query(rig, name) == str(hi)


@pytest.mark.parametrize("name", ["I80", "I3380", "I5013", "I6713"])
def test_neighbours_of_the_ranged_blocks_have_no_range(rig, name):
    """Motor 0 / 33 and CS 0 / 17 do not exist: I80, I3380, I5013 (a gather address), I6713
    keep what they are given."""
    rig.ok(f"{name}=300")
    assert query(rig, name) == "300"


def test_i3_5_assigns_5_modulo_4_which_is_1_the_manual_example(rig):
    """TUM p243: I3 has the range 0..3 (4 values); I3=5 assigns 5 mod 4 = 1, no error."""
    reply = rig.cmd("I3=5")
    assert reply.error is None
    assert query(rig, "I3") == "1"


@pytest.mark.parametrize(
    ("assign", "name", "answer"),
    [
        ("I3=-1", "I3", "3"),  # a negative value comes in from the top of the range
        ("I3=-6", "I3", "2"),
        ("I41=16", "I41", "0"),  # 0..15 (TSRM p57)
        ("I40=65536", "I40", "0"),  # 0..65,535 (TSRM p57); 0 = the 4095 default count
        ("I60=-1", "I60", "15"),  # 0..15 (TSRM p65)
        ("I5000=5", "I5000", "1"),  # gather buffer mode 0..3 (TSRM p170)
        ("I180=9", "I180", "1"),  # Ixx80 0..7 (TSRM p136)
        ("I1680=-2", "I1680", "6"),  # every motor has it (motor 16)
        ("I5113=266", "I5113", "10"),  # Isx13 0..255 ms (TSRM p177)
        ("I6692=3", "I6692", "1"),  # Isx92 0..1 of CS 16
    ],
)
def test_out_of_range_values_roll_over_into_the_range_without_an_error(
    rig, assign, name, answer
):
    assert rig.cmd(assign).error is None
    assert query(rig, name) == answer


def test_fractions_are_truncated_before_rolling_over(rig):
    """[INF] "modulo arithmetic (truncation)": toward zero first, then modulo."""
    rig.ok("I3=2.7")
    assert query(rig, "I3") == "2"
    rig.ok("I3=-1.5")  # -1 -> 3
    assert query(rig, "I3") == "3"


def test_i3_star_restores_the_default_after_a_rolled_over_write(rig):
    rig.ok("I3=7")
    assert query(rig, "I3") == "3"
    rig.ok("I3=*")
    assert query(rig, "I3") == f"{default_i(3):g}"


def test_variables_without_a_limited_range_keep_any_value(rig):
    """Floats and full words have nothing to roll over: Ixx16 keeps 2.5, I10 a large count."""
    rig.ok("I116=2.5 I130=12345678 I5189=0.125 I165=-3")
    assert [query(rig, v) for v in ("I116", "I130", "I5189", "I165")] == [
        "2.5", "12345678", "0.125", "-3",
    ]


def test_every_factory_default_lies_in_its_range():
    """A default outside its range would mean the range is wrong."""
    assert {n: FACTORY[n] for n in RANGES if roll_over(n, FACTORY[n]) != FACTORY[n]} == {}


def test_a_plc_line_i5_equals_6_rolls_over_to_2_and_switches_the_plc_classes(rig):
    """PLC 0 (allowed by the default I5=1) writes I5=6 -> 2: foreground off, background on."""
    rig.ok("OPEN PLC 0 CLEAR")
    rig.ok("M1=M1+1")
    rig.ok("I5=6")
    rig.ok("CLOSE")
    rig.ok("OPEN PLC 1 CLEAR")
    rig.ok("M2=M2+1")
    rig.ok("CLOSE")
    rig.ok("ENABLE PLC 0,1")
    rig.run_for(0.1)
    assert query(rig, "I5") == "2"
    m1 = [e for _, _, e in rig.events("mvar") if e["name"] == "M1"]
    m2 = [e for _, _, e in rig.events("mvar") if e["name"] == "M2"]
    assert len(m1) == 1 and len(m2) > 10  # PLC 0 scanned once, then I5=2 stopped it


def test_a_motion_program_line_rolls_over_like_an_on_line_command(rig):
    rig.ok("OPEN PROG 1 CLEAR")
    rig.ok("I59=6")  # 0..3 (TSRM p65)
    rig.ok("TM100")
    rig.ok("X10")
    rig.ok("CLOSE")
    rig.ok("&1 B1 R")
    rig.run_until_idle()
    assert [e["state"] for _, _, e in rig.events("program")] == ["running", "stopped"]
    assert query(rig, "I59") == "2"


def test_rest_writes_and_config_follow_the_same_rule(make_rig):
    rig = make_rig(i3=6, i5113=300)
    assert rig.c.get_variable("I3") == 2.0
    assert rig.c.get_variable("I5113") == 44.0
    rig.c.set_variable("I3", 5)
    assert rig.c.get_variable("I3") == 1.0


def test_i41_bit_0_locks_motor_variables_the_write_is_ignored_without_error(rig):
    """TSRM p57: with I41 bit 0 set, I100..I4899 cannot be changed; no error; I41=0 unlocks."""
    before = query(rig, "I130")
    rig.ok("I41=1")
    reply = rig.cmd("I130=5")
    assert reply.error is None and reply.reply == ""
    assert query(rig, "I130") == before
    rig.ok("I3230=77")  # motor 32's block is locked too
    assert query(rig, "I3230") == before
    rig.ok("I41=0 I130=5 I41=1")
    rig.ok("I130=*")  # [INF] restoring a default is a write as well
    assert query(rig, "I130") == "5"
    rig.ok("I41=0 I130=*")
    assert query(rig, "I130") == before
    rig.ok("I5113=7 I59=1")  # other sets and the global variables stay writable
    assert (query(rig, "I5113"), query(rig, "I59")) == ("7", "1")
    rig.ok("I41=0")
    rig.ok("I130=5")
    assert query(rig, "I130") == "5"


@pytest.mark.parametrize(
    ("i41", "locked", "free"),
    [
        (2, "I5113", "I130"),  # bit 1: I5100..I6699
        (2, "I6699", "I6800"),
        (4, "I6800", "I5113"),  # bit 2: I6800..I7999
        (4, "I7999", "I8000"),
        (8, "I8000", "I7999"),  # bit 3: I8000..I8191
        (8, "I8191", "I4899"),
        (1, "I4899", "I5100"),  # bit 0 ends at I4899; I4900.. and I5000.. are global
        (1, "I100", "I4900"),
        (2, "I5100", "I5099"),
        (2, "I6699", "I6700"),  # I6700..I6799 belong to no set
        (4, "I6800", "I6799"),
        (15, "I100", "I99"),
    ],
)
def test_each_i41_bit_locks_its_own_set_only(rig, i41, locked, free):
    rig.ok(f"I41={i41}")
    old = query(rig, locked)
    assert old != "3"
    rig.ok(f"{locked}=3 {free}=3")
    assert query(rig, locked) == old
    assert query(rig, free) == "3"


def test_a_locked_write_from_a_running_plc_is_ignored(rig):
    """TSRM p57: "either an on-line command or a buffered program command"."""
    before = query(rig, "I130")
    rig.ok("I41=1")
    rig.ok("OPEN PLC 0 CLEAR")
    rig.ok("I130=9 P1=P1+1")
    rig.ok("CLOSE")
    rig.ok("ENABLE PLC 0")
    rig.run_for(0.05)
    assert float(query(rig, "P1")) > 5  # the PLC ran, its other statement took effect
    assert query(rig, "I130") == before
