"""M-variable definitions: stored, reported in the card's format, values through them
(PSRM p252-262; TUM p246; spec pmac.md §11.7)."""

from __future__ import annotations

import pytest


def test_an_undefined_m_variable_reports_star(rig):
    assert rig.ok("M1->") == "*"
    assert rig.ok("M1..3->") == "*\r*\r*"


@pytest.mark.parametrize(
    ("typed", "reported"),
    [
        ("X:$078802,8,1", "X:$78802,8"),
        ("Y:$78802,8", "Y:$78802,8"),
        ("Y:$78003,8,16,S", "Y:$78003,8,16,S"),
        ("X:$078003,24,S", "X:$78003,24,S"),
        ("X:$78001,24", "X:$78001,24"),
        ("x$7000f,0,8", "X:$7000F,0,8"),
        ("D:$00008B", "D:$8B"),
        ("L:$2041", "L:$2041"),
        ("DP:$060401", "DP:$60401"),
        ("F:$0607FF", "F:$607FF"),
        ("*", "*"),
    ],
)
def test_a_definition_is_reported_back_in_the_cards_short_form(rig, typed, reported):
    rig.ok(f"M10->{typed}")
    assert rig.ok("M10->") == reported


def test_a_range_reports_one_definition_per_line(rig):
    rig.ok("M1->Y:$78802,8 M2->Y:$78802,9 M4->D:$8B")
    assert rig.ok("M1..5->").split("\r") == ["Y:$78802,8", "Y:$78802,9", "*", "D:$8B", "*"]


def test_i9_bit_0_reports_whole_statements(rig):
    rig.ok("M11->Y:$FFC2,8")
    rig.ok("I9=3")
    assert rig.ok("M11->") == "M11->Y:$FFC2,8"


def test_a_range_definition_and_the_star_reset(rig):
    rig.ok("M1..3->X:$10,0,8")
    assert rig.ok("M1..3->") == "X:$10,0,8\rX:$10,0,8\rX:$10,0,8"
    rig.ok("M0..8191->*")
    assert rig.ok("M1..3->") == "*\r*\r*"


def test_output_bits_share_their_word(rig):
    """Two bits and a byte of one Y word: each M-variable sees the others' writes."""
    rig.ok("M1->Y:$78802,8 M2->Y:$78802,9 M9->Y:$78802,8,8")
    rig.ok("M1=1")
    rig.ok("M2=1")
    assert rig.ok("M1 M2 M9") == "1\r1\r3"
    rig.ok("M9=0")
    assert rig.ok("M1 M2") == "0\r0"


def test_fields_roll_over_and_signed_fields_are_twos_complement(rig):
    rig.ok("M20->X:$100,0,8 M21->X:$100,0,8,S")
    rig.ok("M20=257")
    assert rig.ok("M20") == "1"
    rig.ok("M20=255")
    assert rig.ok("M21") == "-1"


def test_float_definitions_keep_fractions(rig):
    rig.ok("M30->L:$2041 M31->D:$2042")
    rig.ok("M30=1.25 M31=2.6")
    assert rig.ok("M30 M31") == "1.25\r3"


def test_a_write_through_a_definition_is_an_mvar_event(rig):
    rig.ok("M1->Y:$78802,8")
    rig.ok("M1=1")
    ev = [e for e in rig.c.log.events() if e.type == "mvar"][-1]
    assert (ev.fields["name"], ev.fields["value"]) == ("M1", 1.0)


def test_motor_status_words_read_through_the_standard_definitions(rig):
    """Mxx40 (in position, Y:$0000C0 bit 0) and the whole words match ``#1?``."""
    rig.ok("M140->Y:$0000C0,0,1 M145->Y:$0000C0,10,1 M150->X:$0000B0,24 M151->Y:$0000C0,24")
    status = rig.ok("#1?")
    assert rig.ok("M150") == str(int(status[:6], 16))
    assert rig.ok("M151") == str(int(status[6:], 16))
    assert rig.ok("M140") == str(int(status[6:], 16) & 1)
    # motor 2's data block is $80 further on
    rig.ok("M250->X:$000130,24")
    assert rig.ok("M250") == str(int(rig.ok("#2?")[:6], 16))


def test_cs_status_words_read_through_definitions(rig):
    rig.ok("M180->X:$002040,24 M181->Y:$00203F,24 M182->Y:$002040,24 M280->X:$2140,24")
    words = rig.ok("&1??")
    assert rig.ok("M180 M181 M182") == "\r".join(
        str(int(words[i : i + 6], 16)) for i in (0, 6, 12))
    assert rig.ok("M280") == str(int(rig.ok("&2??")[:6], 16))


def test_status_registers_are_read_only(rig):
    rig.ok("M150->X:$0000B0,24")
    before = rig.ok("M150")
    rig.ok("M150=0")
    assert rig.ok("M150") == before


def test_motor_position_register_in_units_of_ixx08_times_32(rig):
    """Mxx62 -> D:$00008B: actual position in 1/(Ixx08*32) counts (Ixx08 = 96)."""
    rig.ok("M162->D:$00008B M161->D:$000088")
    rig.ok("#1->1000X")
    rig.ok("&1 DEFINE ROT 200")
    rig.ok("OPEN ROT")
    rig.ok("X2")
    rig.ok("CLOSE")
    rig.ok("&1 B0 R")
    rig.run_for(5.0)
    counts = float(rig.ok("#1P"))
    assert counts == pytest.approx(2000)
    assert float(rig.ok("M162")) == pytest.approx(counts * 96 * 32)
    assert float(rig.ok("M161")) == pytest.approx(counts * 96 * 32)


@pytest.mark.parametrize(
    "bad",
    ["M1->X:$078802,25", "M1->X:$078802,8,3", "M1->Y:$1000000,0", "M1->Q:$10,0",
     "M1->X:$10,8,1,Z", "M8192->X:$10,0", "M1->X:$10,20,8"],
)
def test_a_malformed_definition_is_err003_and_changes_nothing(rig, bad):
    rig.ok("M1->Y:$78802,8")
    r = rig.cmd(bad)
    assert (r.reply, r.error) == ("", "ERR003")
    assert rig.ok("M1->") == "Y:$78802,8"
    assert rig.ok("M8191->") == "*"


def test_writing_mxx62_sets_the_motor_position_without_motion(rig):
    """What dls-backup-bl's restore does: ``M162 = counts/(1/(Ixx08*32))`` after CTRL-K."""
    rig.ok("M162->D:$00008B")
    rig.ok("M162 = 1234/0.0003255208333")  # 1234 counts * 96 * 32
    assert float(rig.ok("#1P")) == pytest.approx(1234, abs=0.1)
    assert float(rig.ok("M162")) == pytest.approx(1234 * 3072, rel=1e-6)
    assert rig.ok("#2P") == "0"


@pytest.mark.parametrize(
    "typed", ["M0-> Y:$78800,0,1", "M0->  y:$078800,0,1", "M0->\tY:$78800,0,1"])
def test_tsrm_p23_blanks_after_the_arrow_are_not_significant(rig, typed):
    """Set-up files write ``M0-> Y:$78800,0,1``: the card ignores blanks outside strings."""
    rig.ok(typed)
    assert rig.ok("M0->") == "Y:$78800,0"
    assert rig.ok("M0-> M0->") == "Y:$78800,0\rY:$78800,0"  # a query is still a query
