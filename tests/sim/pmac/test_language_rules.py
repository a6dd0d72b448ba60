"""Small rules of the Turbo program language (spec §12.1, §12.5, §12.9; TUM p252, p259;
TSRM p268; PSRM p313), checked on the terminal and the event log."""

from __future__ import annotations

import pytest
from motionsim.sim.errors import ParseError
from motionsim.sim.pmac.tasks.plc import compile_plc


def test_clipper_startup_delete_trace_is_accepted_and_changes_nothing(rig):
    """Delta Tau's Clipper set-up file starts ``CLOSE``, ``DELETE GATHER``, ``DELETE TRACE``:
    valid on-line commands; no trace buffer is simulated, so nothing changes."""
    since = rig.c.log.last_seq
    assert rig.cmd("CLOSE DELETE GATHER DELETE TRACE").error is None
    assert rig.cmd("del trace").error is None
    assert rig.events(since=since) == []
    rig.ok("OPEN PLC 1 CLEAR")
    assert rig.cmd("DELETE TRACE").error == "ERR003"  # an on-line command, not a PLC statement
    rig.ok("CLOSE")


@pytest.mark.parametrize(("line", "column"), [
    ("IF((P1>-20) AND (P1<20))", 4), ("WHILE ((P1>2))", 8), ("IF (P1=1 OR (P2=2))", 13),
])
def test_tum_p252_parentheses_around_simple_conditions_are_err003_with_column(
        rig, line, column):
    rig.ok("OPEN PROG 1 CLEAR")
    reply = rig.cmd(line)
    assert reply.error == "ERR003" and f"(column {column})" in reply.detail[1]
    rig.ok("CLOSE")
    assert not rig.c.program_lines(1)  # nothing stored
    # parentheses inside the expressions are fine
    for fine in ["IF ((P1+1)>2)", "IF (P1>-20 AND P1<20)", "WHILE (SIN(P2-P1)!>P300/1000)"]:
        compile_plc(f"{fine}\nEND{fine[:2] if fine[0] == 'I' else 'WHILE'}")
    rig.ok("OPEN PLC 1 CLEAR")
    assert rig.cmd(line).error == "ERR003"
    rig.ok("CLOSE")
    assert rig.c.plcs.plcs[1].program is None
    with pytest.raises(ParseError) as e:
        compile_plc(line)
    assert e.value.column == column


def test_psrm_p313_a_one_line_else_lists_apart_from_its_statement(rig):
    rig.ok("OPEN PROG 1 CLEAR")
    for line in ["IF (P1 !< 5) X10", "ELSE X-10"]:
        rig.ok(line)
    rig.ok("CLOSE")
    assert rig.ok("LIST PROG 1").split("\r") == ["IF(P1!<5)X10", "ELSE X-10", "RET"]
    # In a PLC the card moves a one-line ELSE's statements to the next program line.
    rig.ok("OPEN PLC 1 CLEAR")
    for line in ["IF (P1=1)", "P2=1", "ELSE P2=2", "ENDIF"]:
        rig.ok(line)
    rig.ok("CLOSE")
    assert rig.ok("LIST PLC 1").split("\r") == ["IF(P1=1)", "P2=1", "ELSE", "P2=2", "ENDI",
                                                "RET"]


def test_tsrm_p268_the_definition_offset_is_in_the_motor_position(rig):
    """``#3->2000Z-6000``: the motor is at 2000·Z − 6000. The definition commands no motion;
    PMATCH (TUM p259) starts Z from the motor through the equation (Z=3 at motor 0), and a
    programmed Z0 takes the motor to −6000."""
    rig.ok("&1 #3->2000Z-6000")
    assert rig.ok("#3P") == "0"
    rig.ok("&1 PMATCH")
    assert rig.c.positions(1)["Z"] == 3.0
    rig.ok("OPEN PROG 1 CLEAR")
    rig.ok("LINEAR TA10 TS0 TM100 Z0")
    rig.ok("CLOSE")
    rig.ok("&1 B1 R")
    rig.run_for(2.0)
    assert rig.ok("#3P") == "-6000"
    rig.ok("&1 UNDEFINE")
    assert rig.ok("#3P") == "-6000"  # the motor stays where it is
