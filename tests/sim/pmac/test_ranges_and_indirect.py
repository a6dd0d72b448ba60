"""Indirect and range variables, motor lists (TSRM p328; TUM p243; PSRM p252-253; spec §12.4).

On-line and in PLC programs; the PLC cases are asserted on the event log (``mvar`` events,
servo cycles).
"""

from __future__ import annotations

import pytest


def enter(rig, *lines: str, n: int = 1) -> None:
    rig.ok(f"OPEN PLC {n} CLEAR")
    for line in lines:
        rig.ok(line)
    rig.ok("CLOSE")


def test_tum_p243_indirect_i_variable_assignment_and_query(rig):
    rig.ok("P1=10")
    rig.ok("I(P1*100+20)=10")
    assert rig.ok("I1020") == "10"
    assert rig.ok("I(P1*100+20)") == "10"


@pytest.mark.parametrize("kind", ["P", "Q", "M"])
def test_spec_12_4_indirect_p_q_m_read_and_written(rig, kind):
    rig.ok("P1=4700")
    rig.ok(f"{kind}(P1+1)=3")
    assert rig.ok(f"{kind}4701") == "3"
    assert rig.ok(f"{kind}(P1+1)") == "3"
    rig.ok(f"P2={kind}(P1+1)*2")
    assert rig.ok("P2") == "6"


def test_spec_12_4_indirect_number_out_of_range_is_err003(rig):
    reply = rig.cmd("P(8000+P1+200)")
    assert reply.error == "ERR003"


@pytest.mark.parametrize("kind", ["P", "Q", "I"])
def test_spec_12_4_indirect_assignment_out_of_range_is_err003_like_its_query(rig, kind):
    """The on-line ``P(expr)=v`` names the variable its query names: one below 0 or above
    8191 is ERR003 for both, and nothing is written."""
    rig.ok("P1=0 P8191=7")
    for index in ("P1-1", "P1+8192"):
        assert rig.cmd(f"{kind}({index})=5").error == "ERR003"
        assert rig.cmd(f"{kind}({index})").error == "ERR003"
    assert rig.ok("P8191") == "7"
    rig.ok("I9=0")  # I8191 is an address I-variable: decimal, not I9 bit 1's hex
    rig.ok(f"{kind}(P1+8191)=3")  # the last number is in range
    assert rig.ok(f"{kind}8191") == "3"


def test_tsrm_p328_range_query_with_count_and_step(rig):
    rig.ok("I130=5 I230=6 I330=7 I430=8")
    assert rig.ok("I130,4,100").split("\r") == ["5", "6", "7", "8"]


def test_spec_12_4_range_assignment_with_count_and_step_sets_every_cs(rig):
    """Diamond's set-up form ``i5213,15,100=10``: Isx13 of CS 2..16."""
    rig.ok("i5213,15,100=10")
    assert rig.ok("I5213,15,100").split("\r") == ["10"] * 15
    assert rig.ok("I5113") != "10"  # CS 1 is not in the set
    assert rig.ok("I6713") == "0"


def test_psrm_p252_range_assignment_with_dots(rig):
    rig.ok("&2 Q70..99=3540")
    assert rig.ok("&2 Q70..99").split("\r") == ["3540"] * 30
    assert rig.ok("&1 Q70") == "0"
    rig.ok("M10..12=7 P5..6=-1.5")
    assert rig.ok("M10..12 P5..6").split("\r") == ["7", "7", "7", "-1.5", "-1.5"]


def test_spec_12_4_range_assignment_past_8191_is_err003_and_sets_nothing(rig):
    assert rig.cmd("P8190,3,1=1").error == "ERR003"
    assert rig.ok("P8190") == "0"


def test_spec_12_4_ranges_and_indirect_variables_in_a_plc(rig):
    """The motorhome timer form ``i(5111+(n&30)*50+n%2)`` and a range assignment, in a PLC."""
    rig.ok("I5=2")
    enter(rig, "P1=12", "Q(400+P1)=P1*2", "P20..22=Q412", "i5213,15,100=P1",
          "I(5111+(12&30)*50+12%2)=50",
          "M5=I(5111+(12&30)*50+12%2)", "DISPLC1")
    rig.ok("ENABLE PLC 1")
    rig.run_for(rig.period * 5)
    assert rig.ok("Q412") == "24"
    assert rig.ok("P20..22").split("\r") == ["24"] * 3
    assert rig.ok("I5213,15,100").split("\r") == ["12"] * 15
    ((_, _, f),) = [e for e in rig.events("mvar") if e[2]["name"] == "M5"]
    assert f["value"] == 50
    # I(5111+12*50+0) = I5711, CS 6's timer 1, counting down
    assert int(rig.ok("I5711")) < 50


def test_tsrm_home_with_a_motor_list_homes_each_motor(rig):
    rig.ok("#1$ #2$ #3$")
    rig.ok("HOMEZ1,2,3")
    rig.ok("HOME1..2")
    rig.run_for(0.05)
    starts = [f["motor"] for _, _, f in rig.events("jog") if f["command"] == "HM"]
    assert starts == [1, 2]
    assert rig.cmd("HOMEZ1,33").error == "ERR003"


def test_spec_12_4_range_assignment_in_a_motion_program_runs_with_the_program(rig):
    """Stored in a PROG (not executed at entry), listed back, executed when the program runs."""
    port = rig.c.open_port("h")
    rig.ok("&1 #1->X", port)
    rig.ok("OPEN PROG 7 CLEAR", port)
    rig.ok("P10..12=5 Q70,3,10=P10+1", port)
    rig.ok("X1", port)
    rig.ok("CLOSE", port)
    assert rig.ok("P10") == "0"
    assert rig.ok("LIST PROG 7").split("\r")[0] == "P10..12=5Q70,3,10=P10+1"
    rig.ok("&1 B7 R")
    rig.run_until_idle()
    assert rig.ok("P10..12 Q70 Q80 Q90 Q71").split("\r") == ["5"] * 3 + ["6"] * 3 + ["0"]


def test_psrm_p252_a_dotted_range_sets_its_two_ends_and_nothing_beyond(rig):
    rig.ok("P10..12=4")
    assert rig.ok("P9..13").split("\r") == ["0", "4", "4", "4", "0"]
    rig.ok("P20..20=5")  # a range of one variable
    assert rig.ok("P19..21").split("\r") == ["0", "5", "0"]
