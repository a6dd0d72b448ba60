"""Addressing and card set-up of issue 37 item 5.

* ``DEFINE COMP`` (TSRM p302-303; PSRM p207-210): "The next {entries} constants sent ... will
  be placed into this table" ((rows+1)(columns+1)-1 for a 2D table); a constant is P0= "unless
  a ... compensation table ... has been defined but not filled" (PUM p150); refused with ERR003
  when a ROTARY, LOOKAHEAD or GATHER buffer exists, or a COMP table of a lower-numbered motor.
* ``OPEN SERVO`` (the user-written servo buffer) is valid and not simulated: answered by name.
* ``CLEAR`` with the rotary buffers open (a PComm32 host sends ``OPEN ROT`` ``CLEAR``): the
  open buffer is erased (spec §11.8 "CLEAR erases the open buffer"; the Turbo page itself
  was not found, spec §11.12) ``[INF]`` the addressed CS's lines not yet calculated.
* L-variables of compiled PLCs (``L35->Y:$078802,2,1``; PUM-V p238-245: PLCC source): their
  definitions are kept and a PLCC reads and writes memory through them.
* ``ADDRESS#P{n}`` / ``ADDRESS&P{n}``: in a motion program stored; in a PLC answered by name
  as not simulated, the PLC unchanged.
"""

from __future__ import annotations

import pytest


def _p0(rig):
    return rig.ok("P0")


# -- DEFINE COMP ---------------------------------------------------------------------------


def test_tsrm_p303_the_entries_follow_define_comp_and_are_not_commands(rig):
    rig.ok("P0=9")
    rig.ok("#2 DEFINE COMP 4,#2,#1,1000")
    rig.ok("10 -20")  # on another line: still entries (1/16 count)
    rig.ok("30 0")
    assert _p0(rig) == "9"  # a bare constant would otherwise be P0= (TUM p244)
    assert rig.c.comp_tables[2].values == [10, -20, 30, 0]
    rig.ok("5")  # the table is full: commands again
    assert _p0(rig) == "5"


def test_psrm_p210_a_two_dimensional_table_takes_rows_plus_one_times_columns_plus_one_less_one(rig):
    rig.ok("#1 DEFINE COMP 2.1,#1D,#2,100,200")
    rig.ok("1 2 3 4 5")
    assert rig.c.comp_tables[1].values == [1, 2, 3, 4, 5]
    rig.ok("7")
    assert _p0(rig) == "7"


def test_tsrm_p303_define_comp_with_a_rotary_buffer_is_err003_and_defines_nothing(rig):
    rig.rotary_setup()
    r = rig.cmd("#3 DEFINE COMP 2,10")
    assert r.error == "ERR003" and "rotary" in r.detail[1]
    assert rig.c.comp_tables == {}
    rig.ok("4")
    assert _p0(rig) == "4"


def test_tsrm_p303_comp_tables_are_defined_high_to_low_and_deleted_low_to_high(rig):
    rig.ok("#2 DEFINE COMP 1,10")
    rig.ok("0")
    assert rig.cmd("#3 DEFINE COMP 1,10").error == "ERR003"
    rig.ok("#1 DEFINE COMP 1,10")
    rig.ok("0")
    assert rig.cmd("#2 DELETE COMP").error == "ERR003"
    rig.ok("#1 DELETE COMP")
    rig.ok("#2 DELETE COMP")
    assert rig.c.comp_tables == {}


def test_a_non_integer_entry_is_err003_and_keeps_the_table_as_it_was(rig):
    rig.ok("#1 DEFINE COMP 3,300")
    rig.ok("1")
    r = rig.cmd("2 X")
    assert r.error == "ERR003" and "integer constant" in r.detail[1]
    assert rig.c.comp_tables[1].values == [1]
    rig.ok("2 3")
    assert rig.c.comp_tables[1].values == [1, 2, 3]


# -- OPEN SERVO, CLEAR in the rotary buffer --------------------------------------------------


def test_open_servo_is_answered_by_name(rig):
    r = rig.cmd("OPEN SERVO")
    assert r.error == "ERR003"
    assert r.detail[0] == "not_simulated" and r.detail[1].startswith("OPEN SERVO ")
    assert rig.c.buffer_holder is None


def test_clear_with_the_rotary_open_erases_the_lines_not_yet_calculated(rig):
    rig.rotary_setup()
    port = rig.c.open_port("host")
    rig.ok("OPEN ROT", port)
    for line in ("X1", "X2", "X3"):
        rig.ok(line, port)
    assert rig.c.rotary(1)["lines_ahead"] == 3
    since = rig.c.log.last_seq
    rig.ok("CLEAR", port)
    rot = rig.c.rotary(1)
    assert (rot["lines_ahead"], rot["used_words"]) == (0, 0)
    assert [f["level"] for _, _, f in rig.events("breq", since=since)][-1] is True
    rig.ok("TM100 X5", port)
    rig.ok("CLOSE", port)
    rig.ok("R")
    rig.run_until_idle()
    assert rig.c.positions(1) == {"X": pytest.approx(5.0)}
    assert sorted(rig.by_n("move_start")) == [4]


def test_clear_with_nothing_open_is_still_err005(rig):
    assert rig.cmd("CLEAR").error == "ERR005"


# -- L-variables of compiled PLCs -----------------------------------------------------------


def test_l_variable_definitions_are_kept_and_reported_like_m_definitions(rig):
    rig.ok("L35->Y:$078802,2,1")
    assert rig.ok("L35->") == "Y:$78802,2"
    rig.ok("I9=1")
    assert rig.ok("L35->") == "L35->Y:$78802,2"
    assert rig.ok("M35->") == "M35->*"  # the M-variable of the same number is untouched


def test_pum_v_p238_a_plcc_reads_and_writes_memory_through_its_l_variables(rig):
    rig.ok("I5=3")
    rig.ok("L40->Y:$10F0,0,8")
    rig.ok("OPEN PLCC 4")
    rig.ok("CLEAR")
    rig.ok("L40=7")
    rig.ok("L41=L40*2")
    rig.ok("P1=L41")
    rig.ok("CLOSE")
    rig.ok("ENABLE PLCC 4")
    rig.run_for(0.1)
    assert rig.ok("P1") == "14"
    assert rig.ok("RY:$10F0") == "7"  # L40 is that memory byte


# -- ADDRESS#P / ADDRESS&P --------------------------------------------------------------------


def test_address_by_p_variable_in_a_motion_program_is_stored(rig):
    rig.ok("OPEN PROG 3 CLEAR")
    rig.ok("ADDRESS#P1")
    rig.ok("ADR&P2")
    rig.ok("CLOSE")
    assert rig.ok("LIST PROG 3").replace(" ", "").split("\r") == ["ADR#P1", "ADR&P2", "RET"]


def test_address_by_p_variable_in_a_plc_addresses_what_the_p_variable_holds(rig):
    """``ADDRESS&P{n}`` / ``ADDRESS#P{n}`` in a PLC: the CS (its Q-variables, the ``CMD``s'
    start) and motor are the P-variable's value when the statement runs ``[BK]``."""
    rig.ok("P10=3 P11=2")
    rig.ok("OPEN PLC 4 CLEAR")
    for line in ("ADDRESS&P10", "ADR#P11", "Q5=7", "P10=1", "ADDRESS&P10", "Q5=9",
                 "DISABLE PLC 4"):
        rig.ok(line)
    rig.ok("CLOSE")
    assert rig.ok("LIST PLC 4").replace(" ", "").upper().splitlines()[:2] == ["ADR&P10",
                                                                             "ADR#P11"]
    rig.ok("I5=2 ENABLE PLC 4")
    rig.run_for(0.05)
    plc = rig.c.plcs.plc(4)
    assert rig.c.vars.read("Q", 5, cs=3) == 7 and rig.c.vars.read("Q", 5, cs=1) == 9
    assert (plc.cs, plc.motor) == (1, 2)
