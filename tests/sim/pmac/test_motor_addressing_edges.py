"""``#n->`` axis definitions across coordinate systems and ``#n`` addressing with a PLC open
(TSRM p269-270 ``#n->``; TUM p243 axis definitions; TSRM p23 addressing). Virtual time."""

from __future__ import annotations


def test_tsrm_p270_a_definition_is_reported_and_changed_only_in_its_own_cs(rig):
    rig.ok("&2 #3->1000X")
    assert rig.ok("&1 #3->") == "0"  # not defined in CS 1
    assert rig.ok("&3 #3->") == "0"
    assert rig.ok("&2 #3->") == "1000X"
    for cs in (1, 3):  # redefining it from another CS: ERR003, nothing changes
        reply = rig.cmd(f"&{cs} #3->1000Y")
        assert reply.error == "ERR003"
        assert reply.detail == ("conflict", "motor 3 is defined in coordinate system 2")
    rig.ok("&1 #3->0")  # clearing it from another CS changes nothing
    assert rig.ok("&2 #3->") == "1000X"
    rig.ok("&2 #3->0")
    assert rig.ok("&2 #3->") == "0"


def test_tum_p243_a_new_offset_moves_no_motor(rig):
    """Redefining ``#1->1000X+500`` as ``#1->1000X+200`` commands no motion: the motor keeps
    its position and the axis, matched to it, is (2000 - 200) / 1000."""
    rig.ok("&1 #1->1000X+500")
    rig.ok("#1J=2000")
    rig.run_until_idle(3)
    rig.ok("&1 #1->1000X+200")
    rig.run_for(0.2)
    assert rig.ok("#1P") == "2000"
    rig.ok("&1 PMATCH")
    assert rig.c.positions(1)["X"] == 1.8


def test_motor_addressing_acts_on_line_while_the_port_holds_a_plc_open(rig):
    """``#2`` sent while the port enters a PLC addresses motor 2 at once (a host's polls keep
    working while it enters a PLC ``[INF]``): ``P`` after ``CLOSE`` reports motor 2."""
    rig.ok("#2J=1500")
    rig.run_until_idle(3)
    port = rig.c.open_port("host")
    rig.ok("#1", port)
    rig.ok("OPEN PLC 1 CLEAR", port)
    rig.ok("#2", port)
    rig.ok("CLOSE", port)
    assert rig.ok("P", port) == "1500"


def test_tsrm_motor_numbers_1_to_32_take_a_definition_33_is_err003(rig):
    assert rig.cmd("#32->1000X").error is None
    assert rig.cmd("#33->1000X").error == "ERR003"
    assert rig.cmd("#0->1000X").error == "ERR003"


def test_spec_12_4_an_indirect_query_below_0_is_err003(rig):
    assert rig.cmd("P(P1-1)").error == "ERR003"
    assert rig.cmd("P(P1+8192)").error == "ERR003"
    assert rig.ok("P(P1+8191)") == "0"


def test_tsrm_i9_an_address_i_variable_reads_in_decimal_with_i9_0_hex_with_i9_2(rig):
    """I9 bit 1 (TSRM I9): address I-variables (Ixx03 here) are reported in hex when set."""
    assert rig.ok("I103") == "$3502"
    rig.ok("I9=0")
    assert rig.ok("I103") == "13570"
    rig.ok("I9=2")
    assert rig.ok("I103") == "$3502"
