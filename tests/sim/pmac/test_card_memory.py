"""The card memory programs use (issue 24 item 2): M-variable definition words at $4000+n,
the user buffer, ``WL:`` of 48-bit floats, ``DELETE ALL`` / ``UNDEFINE ALL``, timing
registers (sim/pmac/card/{mvars,memory_map,user_buffer,registers,pmac_float}.py)."""

from __future__ import annotations

import math
import random

import pytest
from motionsim.sim.pmac.card import pmac_float

UB = "DEFINE UBUFFER $5000"  # Diamond's clipper size: buffer $B800..$107FF


def _err(rig, line: str) -> str:
    reply = rig.cmd(line)
    assert reply.error is not None, line
    return str(reply.error)


def test_tum_p246_definition_word_y_half_holds_the_address_and_repoints(rig):
    rig.ok(UB)
    rig.ok("M4000->L:$B850")
    rig.ok("M4012->Y$4FA0,0,24")  # the colon-less form of Diamond's Time_Adr
    assert rig.ok("M4012") == str(0xB850)
    rig.ok("WL:$B851,$600000000800")  # 1.5
    rig.ok("M4012=$B851")
    assert rig.ok("M4000->") == "L:$B851"
    assert rig.ok("M4000") == "1.5"
    rig.ok("M4000=-2.25")  # written through the re-pointed definition
    assert rig.ok("RL:$B851") == "-2.25"
    assert rig.ok("RL:$B850") == "0"


def test_tum_p246_repointing_keeps_the_type_and_width(rig):
    rig.ok(UB)
    rig.ok("M4010->X:$B830,0,4")
    rig.ok("M4022->Y:$4FAA,0,24")
    rig.ok("WL:$B860,$3000064")
    rig.ok("M4022=$B860")
    assert rig.ok("M4010->") == "X:$B860,0,4"
    assert rig.ok("M4010") == "3"


def test_tum_p246_definition_word_is_readable_from_the_host(rig):
    rig.ok("M7->Y:$78800,7,1")
    assert rig.ok("RY:$4007") == str(0x78800)
    rig.ok("WY:$4007,$78801")
    assert rig.ok("M7->") == "Y:$78801,7"
    # a self-referenced M-variable's word reads 0 and stays self-referenced
    assert rig.ok("RY:$4008") == "0"
    rig.ok("WY:$4008,$1234")
    assert rig.ok("M8->") == "*"


def test_tum_p246_x_half_retypes_with_its_own_code(rig):
    rig.ok("M1->Y:$78800,0,8")
    rig.ok("M2->Y:$78800,0,24")
    code = int(rig.ok("RX:$4002"))
    rig.ok(f"WX:$4001,{code}")
    assert rig.ok("M1->") == "Y:$78800,24"
    rig.ok("WX:$4001,$FFFFFF")  # not a code: nothing changes
    assert rig.ok("M1->") == "Y:$78800,24"


def test_pum_p150_array_writing_through_a_moving_definition(rig):
    """The manual's sine-table loop: point M0 with M10, write through M0."""
    rig.ok(UB)
    rig.ok("M0->L:$C000")
    rig.ok("M10->Y:$4000,0,24")
    for k in range(8):
        rig.ok(f"M10={0xC000 + k} M0=SIN({k * 10})")
    values = rig.ok("RL:$C000,8").split()
    assert [float(v) for v in values] == pytest.approx(
        [math.sin(math.radians(k * 10)) for k in range(8)], rel=1e-9, abs=1e-10)


def test_tsrm_p164_define_ubuffer_reserves_the_top_of_open_memory(rig):
    since = rig.c.log.last_seq
    rig.ok("DEF UBUF 512")
    assert rig.c.vars.I(4908) == 0x010600
    assert rig.events("ubuffer", since=since)[0][2] == {"first": 0x010600, "last": 0x0107FF}
    rig.ok("WY:$10600,7")
    rig.ok("WY:$107FF,9")
    assert rig.ok("RY:$10600") == "7"
    assert "ERR003" in _err(rig, "DEFINE UBUFFER 16")  # one user buffer only


def test_a_write_outside_the_user_buffer_is_err003_and_overwrites_nothing(rig):
    rig.ok("DEF UBUF 512")
    rig.ok("WL:$10600,5")
    assert "ERR003" in _err(rig, "WL:$105FE,1,2,3")  # runs from program memory into it
    assert rig.ok("RL:$10600") == "5"
    assert rig.ok("RL:$105FF") == "0"
    rig.ok("M1->Y:$A000,0,24")  # program memory: an M-variable write there is dropped
    rig.ok("M1=77")
    assert rig.ok("M1") == "0"
    assert "ERR003" in _err(rig, "WX:$A000,1")


def test_wl_writes_the_epics_drivers_time_and_user_words(rig):
    """``WL:$addr,$<u><tttttt>``: user code in X bits 0-3, time (µs) in Y (spec §12.7)."""
    rig.ok(UB)
    rig.ok("WL:$B850,$1000064,$20003E8")
    rig.ok("M4010->X:$B850,0,4 M4000->Y:$B850,0,24")
    assert rig.ok("M4010") == "1" and rig.ok("M4000") == "100"
    assert rig.ok("RHX:$B851") == "000002" and rig.ok("RY:$B851") == "1000"


def _double_to_pmac_float(value: float) -> int:
    """The EPICS driver's encoder, re-stated independently for the test (EPH l. 415-480)."""
    if value == 0.0:
        return 0
    a, exp = abs(value), 0
    while a >= 2.0:
        a /= 2.0
        exp += 1
    while a < 1.0:
        a *= 2.0
        exp -= 1
    m = abs(value)
    while m < 34359738368.0:
        m *= 2.0
    mant = int(m / 2.0)
    if value < 0:
        mant = 0xFFFFFFFFF - mant
    return (mant << 12) + exp + 0x800


def test_wl_of_host_encoded_floats_reads_back_through_l_m_variables(rig):
    rig.ok(UB)
    rng = random.Random(24)
    # the host encodes |v| < 2**35 only
    values = [rng.uniform(-1e6, 1e6) for _ in range(40)] + [1e-6, -3.0, 0.0, 2**30]
    for k, v in enumerate(values):
        assert pmac_float.encode(v) == _double_to_pmac_float(v)
        rig.ok(f"WL:${0xB900 + k:X},${_double_to_pmac_float(v):X}")
    rig.ok("M4001->L:$B900 M4013->Y:$4FA1,0,24")
    for k, v in enumerate(values):
        rig.ok(f"M4013={0xB900 + k}")
        got = rig.c.vars.read("M", 4001)
        assert got == pytest.approx(v, rel=2**-33, abs=0)


def test_l_and_d_words_are_the_x_and_y_words_of_one_address(rig):
    rig.ok(UB)
    rig.ok("WD:$B800,-2")
    assert rig.ok("RHX:$B800") == "FFFFFF" and rig.ok("RHY:$B800") == "FFFFFE"
    rig.ok("WX:$B801,$600000 WY:$B801,$800")
    assert rig.ok("RL:$B801") == "1.5"


def test_delete_all_erases_the_buffers_and_undefine_all_the_axes(rig):
    rig.ok(UB)
    rig.ok("WY:$B800,5")
    rig.ok("&1 DEFINE ROT 100")
    rig.ok("&1 #1->1000X &2 #2->1000Y")
    rig.ok("DELETE ALL")
    assert rig.c.coord_system(1).rotary is None
    assert rig.c.vars.mvars.ubuffer is None
    assert "ERR003" in _err(rig, "WY:$B800,5")
    rig.ok("DEF UBUF $5000")
    assert rig.ok("RY:$B800") == "0"  # a new buffer starts clear
    rig.ok("&1 UNDEFINE")
    assert rig.ok("&1 #1->") == "0" and rig.ok("&2 #2->") == "1000Y"
    rig.ok("UNDEFINE ALL")
    assert rig.ok("&2 #2->") == "0"


def test_define_ubuffer_after_a_rotary_buffer_is_refused(rig):
    rig.ok("&1 DEFINE ROT 100")
    assert "ERR003" in _err(rig, "DEFINE UBUFFER 100")
    assert rig.c.vars.mvars.ubuffer is None


def test_servo_counter_register_counts_servo_cycles(rig):
    rig.ok("M100->X:$000000,0,24,S")
    rig.run_for(0.5)
    k = math.floor(rig.c.env.now / rig.period + 1e-9)
    assert rig.c.vars.read("M", 100) == k
    assert k >= math.floor(0.5 / rig.period)


def test_cpu_load_plc_registers_give_the_duty_cycles(rig):
    """M70..M73 as Diamond's CPU-load PLC reads them: phase/servo/RTI task times."""
    rig.ok("M70->X:$FFFF8C,0,24 M71->X:$000037,0,24 M72->Y:$000037,0,24 M73->X:$00000B,0,24")
    rig.run_for(0.2)
    v = rig.c.vars
    m70, m71, m72 = v.read("M", 70), v.read("M", 71), v.read("M", 72)
    phase_period = rig.period / (v.I(7002) + 1)
    assert m70 == round(phase_period * 240e6 / 2)
    assert m71 == 0
    servo_duty = m72 / (m70 * (v.I(7002) + 1))
    assert servo_duty == pytest.approx(rig.c.background.load()["servo"], rel=1e-3)
