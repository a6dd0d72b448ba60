"""I9 reporting, several commands per line, and errors explained (spec pmac.md §2.3, §11.5)."""

from __future__ import annotations

import pytest


def test_i10_then_nonsense_answers_i10_then_the_error(rig):
    r = rig.cmd("i10 nonsense")
    assert (r.reply, r.error) == ("3713707", "ERR003")


def test_each_query_before_the_failing_command_answers(rig):
    r = rig.cmd("I16 I17 #1-> BOGUS I18")
    assert (r.reply, r.error) == ("5\r10\r0", "ERR003")


def test_a_malformed_line_with_an_assignment_before_the_error_changes_nothing(rig):
    r = rig.cmd("I16 P1=5 BOGUS")
    assert (r.reply, r.error) == ("", "ERR003")
    assert rig.ok("P1") == "0"


@pytest.mark.parametrize("text", ["SAVEX", "RESET", "HOLD"])
def test_an_unknown_word_never_runs_the_letters_it_starts_with(rig, text):
    """``RESET`` must not run ``R`` (the parser reads unknown words letter by letter)."""
    rig.ok("&1 DEFINE ROT 100")
    r = rig.cmd(text)
    assert r.error == "ERR003"
    assert rig.c.coord_system(1).state == "idle"


def test_address_type_i_variables_answer_in_hex_with_factory_i9(rig):
    assert rig.ok("I9") == "2"
    assert rig.ok("I20..23").split("\r") == ["$0", "$0", "$0", "$0"]
    assert rig.ok("I124 I125 I5193 I8000") == "$40001\r$3440\r$2000\r$2F8420"
    assert rig.ok("I108 I116 I5049") == "96\r32\r1"  # not addresses: decimal (I5049: p171)


def test_i9_bit_1_clear_reports_addresses_in_decimal(rig):
    rig.ok("I9=0")
    assert rig.ok("I124") == str(0x40001)


def test_i9_bit_0_set_reports_whole_statements_in_hex(rig):
    rig.ok("I9=3")
    assert rig.ok("I124 I116") == "I124=$40001\rI116=32"


def test_factory_values_the_tools_read(rig):
    """I68 = 15 (16 coordinate systems), Ixx08 = 96 (spec §11.6)."""
    assert rig.ok("I68 I108 I808 I3208") == "15\r96\r96\r96"


def test_out_of_range_variable_numbers_are_err003_and_change_nothing(rig):
    for text in ("I8192", "I8192=1", "P9000=1", "I8190..8192"):
        r = rig.cmd(text)
        assert (r.reply, r.error) == ("", "ERR003"), text


def test_a_not_simulated_command_is_err003_on_the_wire_with_a_detail(rig):
    r = rig.cmd("&1 PASSWORD=ABC")
    assert r.error == "ERR003"
    assert r.detail is not None and r.detail[0] == "not_simulated"
    assert "PASSWORD" in r.detail[1]


def test_a_typo_is_a_parse_error_detail_with_the_column(rig):
    r = rig.cmd("I16 )")
    assert r.error == "ERR003" and r.detail is not None
    assert r.detail[0] == "parse_error" and "column" in r.detail[1]
