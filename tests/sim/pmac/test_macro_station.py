"""MACRO station commands with no ring (TSRM p362-371; PSRM p267; spec §12.8).

The station variables are kept per node and answered in the card's format (one data line per
read); MSR / MSW copy between a station and the card's variables, on-line and from PLCs.
"""

from __future__ import annotations

import pytest


def test_tsrm_p362_ms_read_answers_the_stored_value_as_one_data_line(rig):
    assert rig.ok("MS0,I910") == "0"
    assert rig.ok("ms0, i910=3") == ""
    assert rig.ok("MS0,MI910") == "3"
    assert rig.ok("MACROSLAVE0,I910") == "3"
    assert rig.ok("MS16,I910") == "0"  # another node, MACRO IC 1


def test_tsrm_p366_msr_and_msw_copy_between_station_and_card_variables(rig):
    rig.ok("MS4,I20=$1F")
    rig.ok("MSR4,I20,P100 MSR4,MI20,M7")
    assert rig.ok("P100") == "31"
    assert rig.ok("M7") == "31"
    rig.ok("&2 Q5=-2.5")
    rig.ok("&2 MSW4,I21,Q5")
    assert rig.ok("MS4,I21") == "-2.5"
    rig.ok("MACROSLVWRITE4,I22,P100")
    assert rig.ok("MS 4 , I22") == "31"


def test_tsrm_p366_msr_in_a_plc_runs_every_scan(rig):
    rig.ok("I5=2 MS0,I910=7")
    rig.ok("OPEN PLC 3 CLEAR")
    rig.ok("MSR0,i910,P200")
    rig.ok("P201=P200+1 DISPLC3")
    rig.ok("CLOSE")
    assert rig.ok("P200") == "0"  # stored, not executed, while the PLC was open
    rig.ok("ENABLE PLC 3")
    rig.run_for(rig.period * 5)
    assert rig.ok("P201") == "8"


@pytest.mark.parametrize(("line", "reply"), [
    ("MSVER0", "1.104"), ("MS VER 5", "1.104"), ("MSDATE0", "03/27/97"), ("MSCONFIG2", "0"),
    ("MS $$$0", ""), ("MS$$$***1", ""), ("MSSAVE0", ""), ("MS SAVE 4", ""), ("MSCLRF3", ""),
])
def test_tsrm_p368_station_set_up_commands_are_answered(rig, line, reply):
    assert rig.ok(line) == reply


def test_tsrm_p368_msconfig_stores_the_configuration_number_and_ms_reset_all_clears(rig):
    rig.ok("MSCONFIG3=37 MS3,I7=9")
    assert rig.ok("MSCONFIG 3") == "37"
    rig.ok("MS$$$***3")
    assert (rig.ok("MSCONFIG3"), rig.ok("MS3,I7")) == ("0", "0")


@pytest.mark.parametrize(("line", "column"), [("MS64,I1", 3), ("MS0,I8192", 6),
                                              ("MSR0,I1,P4096", 10)])
def test_out_of_range_node_or_variable_is_err003_and_stores_nothing(rig, line, column):
    reply = rig.cmd(line)
    assert reply.error == "ERR003"
    assert rig.c.macro_stations.variables == {}


def test_tsrm_p366_msr_in_a_motion_program_is_not_simulated_and_not_run(rig):
    port = rig.c.open_port("h")
    rig.ok("MS0,I910=3")
    rig.ok("OPEN PROG 2 CLEAR", port)
    assert rig.cmd("MSR0,I910,P1", port).error == "ERR003"
    assert rig.c._terminal.detail[0] == "not_simulated"
    assert rig.ok("MS0,I910", port) == "3"  # the on-line read still answers
    rig.ok("CLOSE", port)
    assert rig.ok("P1") == "0"
