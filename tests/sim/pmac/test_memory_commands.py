"""``R[H]{address}[,{count}]`` and ``W{address},{value}...``: the card's memory from the host
(sim/pmac/card/memory_commands.py), on the M-variable memory and its mapped registers."""

from __future__ import annotations

import pytest


def test_an_address_the_model_does_not_hold_reads_zero(rig):
    assert rig.ok("RX:$1000") == "0"
    assert rig.ok("RHX:$10,2") == "000000 000000"
    assert rig.ok("RHY:$10") == "000000"


def test_w_writes_and_r_reads_back_in_decimal_rh_in_hex(rig):
    rig.ok("WX:$1000,5")
    assert rig.ok("RX:$1000") == "5"
    assert rig.ok("RHX:$1000") == "000005"
    assert rig.ok("RHY:$1000") == "000000"  # X and Y are separate words


def test_w_with_several_values_fills_consecutive_words(rig):
    rig.ok("WY:$78800,$FF,-1,12")
    assert rig.ok("RHY:$78800,3") == "0000FF FFFFFF 00000C"
    assert rig.ok("RY:$78801") == "16777215"  # a negative value as its 24-bit word


def test_memory_writes_are_seen_by_m_variables_pointing_there(rig):
    rig.ok("M1->Y:$78802,8,1")
    rig.ok("WY:$78802,$100")
    assert rig.ok("M1") == "1"
    rig.ok("M1=0")
    assert rig.ok("RHY:$78802") == "000000"


def test_r_of_a_motor_status_register_is_the_status_word(rig):
    status = rig.ok("#1?")
    assert rig.ok("RHX:$B0") == status[:6]
    assert rig.ok("RHY:$C0") == status[6:]


def test_w_to_a_status_register_changes_nothing(rig):
    before = rig.ok("#1?")
    rig.ok("WX:$B0,0")
    assert rig.ok("#1?") == before


def test_d_words_read_the_48_bit_position_register(rig):
    rig.ok("#1J=1000")
    rig.run_for(5.0)
    pos = float(rig.ok("#1P"))
    raw = round(pos * float(rig.ok("I108")) * 32)
    assert rig.ok("RD:$8B") == str(raw)
    assert rig.ok("RHD:$8B") == f"{raw & (1 << 48) - 1:012X}"


def test_l_words_read_their_float_and_rhl_their_48_bits(rig):
    rig.ok("WL:$2000,1.5")
    assert rig.ok("RL:$2000") == "1.5"
    assert rig.ok("RHL:$2000") == "600000000800"  # mantissa 1.5·2**34, exponent $800


@pytest.mark.parametrize("line", ["WX:$1000,1.5", "WX:$1000", "RX:$1000000", "RX:$10,0",
                                  "WX:$1000,5,"])
def test_malformed_memory_commands_are_err003_and_write_nothing(rig, line):
    since = rig.c.log.last_seq
    reply = rig.cmd(line)
    assert reply.error is not None and "ERR003" in str(reply.error)
    assert rig.ok("RX:$1000") == "0"
    assert rig.events(since=since) == []


def test_the_last_address_is_ffffff_and_a_count_may_reach_it_not_pass_it(rig):
    assert rig.ok("RX:$FFFFFF") == "0"
    assert rig.ok("RX:$10,1") == "0"
    assert rig.ok("RX:$FFFFFE,2") == "0 0"
    reply = rig.cmd("RX:$FFFFFF,2")
    assert reply.error is not None and "ERR003" in str(reply.error)


def test_w_may_fill_up_to_ffffff_not_past_it(rig):
    rig.ok("WX:$FFFFFE,1,2")
    assert rig.ok("RX:$FFFFFE,2") == "1 2"
    reply = rig.cmd("WX:$FFFFFF,3,4")
    assert reply.error is not None and "ERR003" in str(reply.error)
    assert rig.ok("RX:$FFFFFF") == "2"  # nothing written


def test_w_from_an_odd_address_fills_the_next_words(rig):
    rig.ok("WY:$78801,1,2,3")
    assert rig.ok("RHY:$78801,3") == "000001 000002 000003"


def test_a_negative_fraction_is_refused_for_x_words(rig):
    reply = rig.cmd("WX:$1000,-1.5")
    assert reply.error is not None and "ERR003" in str(reply.error)
    assert rig.ok("RX:$1000") == "0"


def test_d_words_are_48_bit_twos_complement(rig):
    rig.ok("WD:$3000,-1")
    assert rig.ok("RD:$3000") == "-1"
    assert rig.ok("RHD:$3000") == "FFFFFFFFFFFF"
    rig.ok("WD:$3001,$123456789AB")
    assert rig.ok("RHD:$3001") == "0123456789AB"
