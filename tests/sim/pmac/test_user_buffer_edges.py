"""``DEFINE UBUFFER`` size limits and what ``DELETE ALL`` frees (TSRM p164; spec §12.7;
sim/pmac/card/user_buffer.py). The user buffer lies at the top of open memory, $00A000 ...
$0107FF: 1 ... $6800 words fit. Virtual time."""

from __future__ import annotations

import pytest

from .conftest import Rig

OPEN_WORDS = 0x010800 - 0x00A000  # 26 624 words of open memory


@pytest.mark.parametrize(("words", "accepted"), [
    (0, False), (1, True), (OPEN_WORDS, True), (OPEN_WORDS + 1, False)])
def test_tsrm_p164_define_ubuffer_takes_1_to_the_open_memory_size(words, accepted):
    rig = Rig()
    reply = rig.cmd(f"DEFINE UBUFFER {words}")
    assert (reply.error is None) == accepted, reply.error
    if accepted:
        assert rig.c.vars.I(4908) == 0x010800 - words  # I4908: the buffer's first address
    else:
        assert reply.error == "ERR003"
        assert rig.c.vars.mvars.ubuffer is None


def test_tsrm_p164_delete_all_erases_every_word_of_the_user_buffer(rig):
    """After ``DELETE ALL`` the memory the buffer held reads 0 at its first, a middle and its
    last address (reads stay possible; writes there are refused until a new buffer)."""
    rig.ok("DEF UBUF 512")
    for address, value in ((0x10600, 5), (0x10700, 6), (0x107FF, 7)):
        rig.ok(f"WY:${address:X},{value}")
        assert rig.ok(f"RY:${address:X}") == str(value)
    rig.ok("DELETE ALL")
    assert [rig.ok(f"RY:${a:X}") for a in (0x10600, 0x10700, 0x107FF)] == ["0", "0", "0"]
    assert rig.c.vars.I(4908) == 0x1C000  # back to its factory value (the FDUMP's)


def test_tsrm_p164_delete_all_frees_a_lookahead_buffer_and_ubuffer_can_follow(rig):
    rig.ok("&1 DEFINE LOOKAHEAD 50,10")
    assert rig.cmd("DEFINE UBUFFER 10").error == "ERR003"  # other buffers first
    rig.ok("DELETE ALL")
    assert rig.c.coord_system(1).lookahead is None
    rig.ok("DEFINE UBUFFER 10")


def test_delete_all_is_err001_naming_the_first_running_cs(rig):
    """ERR001 while any CS runs a program; the message names the lowest-numbered running
    CS ``[INF]``."""
    rig.ok("OPEN PROG 1 CLEAR")
    rig.ok("LINEAR INC TA10 TS0 TM2000 X1")
    rig.ok("CLOSE")
    rig.ok("&2 #3->1000X &3 #4->1000X")
    rig.ok("&2 B1 R")
    rig.ok("&3 B1 R")
    rig.run_for(0.1)
    reply = rig.cmd("DELETE ALL")
    assert reply.error == "ERR001"
    assert reply.detail is not None and "CS 2 is running" in reply.detail[1]


def test_tsrm_p164_define_and_delete_touch_only_the_user_buffers_words(rig):
    """Words below open memory ($3000) and in the extended user memory ($030000) keep their
    values through ``DEFINE UBUFFER`` (which starts its own range clear) and ``DELETE ALL``."""
    outside = (0x3000, 0x9FFF, 0x30000, 0x3FFFF)
    for k, address in enumerate(outside):
        rig.ok(f"WY:${address:X},{k + 3}")
    rig.ok("DEF UBUF 512")
    assert [rig.ok(f"RY:${a:X}") for a in outside] == ["3", "4", "5", "6"]
    rig.ok("WY:$10600,9")
    rig.ok("DELETE ALL")
    assert [rig.ok(f"RY:${a:X}") for a in outside] == ["3", "4", "5", "6"]
    assert rig.ok("RY:$10600") == "0"


def test_tum_p246_the_x_half_code_carries_offset_width_and_format(rig):
    """An M-variable's definition word at $4000 + n: the X half read from one definition and
    written into another's re-types it to the same field (offset 8, width 4, signed) or the
    same long-float form ``[INF]`` (spec §12.11: the X-half encoding is the simulator's)."""
    rig.ok("M1->Y:$78800,8,4,S")
    rig.ok("M2->Y:$78801,0,24")
    rig.ok(f"WX:$4002,{int(rig.ok('RX:$4001'))}")
    assert rig.ok("M2->") == "Y:$78801,8,4,S"
    rig.ok("M3->L:$78802")
    rig.ok("M4->Y:$78803,0,24")
    rig.ok(f"WX:$4004,{int(rig.ok('RX:$4003'))}")
    assert rig.ok("M4->") == "L:$78803"
    assert rig.ok("RX:$4004") == rig.ok("RX:$4003")  # the same form reads the same code
    rig.ok("M4=1.5")
    assert rig.ok("M4") == "1.5"
