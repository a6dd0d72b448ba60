"""LIST PLC / ROT / FORWARD / INVERSE / GATHER in the card's format (spec pmac.md §11.8)."""

from __future__ import annotations

import pytest

PLC1 = [
    "OPEN PLC 1 CLEAR",
    "IF (M4900 = 0) ; first scan",
    "M4900 = 1",
    "P10=$60000",
    "DISABLE PLC 2..31",
    "I5112 = 1000 * 8388608 / i10",
    "WHILE (I5112 > 0)",
    "ENDWHILE",
    "ENABLE PLC 6",
    "ENDIF",
    'CMD "DEFINE LOOKAHEAD 50,10"',
    "CLOSE",
]

LISTED = [
    "IF(M4900=0)", "M4900=1", "P10=393216", "DISPLC2..31", "I5112=1000*8388608/I10",
    "WHILE(I5112>0)", "ENDW", "ENAPLC6", "ENDI", 'CMD"DEFINE LOOKAHEAD 50,10"', "RET",
]  # fmt: skip


@pytest.fixture
def plc1(rig):
    for line in PLC1:
        rig.ok(line)
    return rig


def test_list_plc_lists_the_decompiled_program_with_ret_added(plc1):
    """Comments gone, upper case, blanks removed, short keywords, hex as decimal, RET."""
    assert plc1.ok("LIST PLC 1").split("\r") == LISTED


def test_list_plc_with_offsets_gives_word_offsets(plc1):
    lines = plc1.ok("LIST PLC 1,0,80").split("\r")
    offsets = [int(line.split(":", 1)[0]) for line in lines]
    assert [line.split(":", 1)[1] for line in lines] == LISTED
    assert offsets[0] == 0 and offsets == sorted(offsets) and len(set(offsets)) == len(offsets)
    # IF(M4900=0) takes 3 words, M4900=1 two (the capture in spec §11.8)
    assert offsets[1:3] == [3, 5]


def test_a_window_lists_the_lines_starting_inside_it(plc1):
    assert plc1.ok("LIST PLC 1,3,2").split("\r") == ["3:M4900=1"]
    assert plc1.ok("LIST PLC 1,3,3").split("\r") == ["3:M4900=1", "5:P10=393216"]


def test_a_start_beyond_the_last_line_is_err003(plc1):
    last = int(plc1.ok("LIST PLC 1,0,200").split("\r")[-1].split(":")[0])
    assert plc1.cmd(f"LIST PLC 1,{last + 1},80").error == "ERR003"
    assert plc1.ok(f"LIST PLC 1,{last},80") == f"{last}:RET"


@pytest.mark.parametrize("cmd", ["LIST PLC 2", "LIST PLC 2,0,80", "LIST PLC 32", "LIST PLC"])
def test_an_empty_or_missing_plc_is_err003(rig, cmd):
    assert rig.cmd(cmd).error == "ERR003"


def test_list_rot_lists_the_lines_not_yet_calculated(rig):
    rig.ok("&1 DEFINE ROT 100")
    rig.ok("OPEN ROT")
    rig.ok("X10 Y20")
    rig.ok("linear X 0.50")
    rig.ok("CLOSE")
    assert rig.ok("&1 LIST ROT").split("\r") == ["X10Y20", "LINX0.5"]


def test_list_rot_without_a_rotary_buffer_is_err003(rig):
    assert rig.cmd("&2 LIST ROT").error == "ERR003"


@pytest.mark.parametrize("kin", ["FORWARD", "INVERSE"])
def test_empty_kinematic_programs_list_no_lines_without_an_error(rig, kin):
    """Every CS has its kinematic buffers: an empty one lists nothing. The EPICS driver reads
    ``&1 list forward,0,1`` word by word and stops at an empty reply
    (pmacCSController::listKinematic); dls-pmacanalyse's ``list forward,0,80`` returns what it
    read on a reply with no offset."""
    for line in (f"&1 LIST {kin},0,80", f"&1 list {kin.lower()},0,1", f"&3 LIST {kin}"):
        r = rig.cmd(line)
        assert (r.reply, r.error) == ("", None), line


def test_list_gather_needs_a_gather_buffer(rig):
    assert rig.cmd("LIST GATHER").error == "ERR003"
    rig.ok("DEFINE GATHER 1000")
    r = rig.cmd("LIST GATHER")
    assert (r.reply, r.error) == ("", None)  # no samples: gathering is not simulated


def test_listing_is_a_report_answered_before_a_malformed_command(plc1):
    r = plc1.cmd("LIST PLC 1,0,3 BOGUS")
    assert (r.reply, r.error) == ("0:IF(M4900=0)", "ERR003")
