"""The kinematic buffers beside the PROGs (TSRM p379 OPEN FORWARD / OPEN INVERSE) and the
refusals of the kinematics commands (ERR007 with a buffer open, ERR001 while a CS runs; TSRM
p269-270, p379). Virtual time."""

from __future__ import annotations

import pytest
from motionsim.sim.pmac.kinematics.subroutine import MAX_STEPS


def _enter(rig, opener: str, line: str) -> None:
    rig.ok(f"{opener} CLEAR")
    rig.ok(line)
    rig.ok("CLOSE")


def _err(rig, line: str) -> str:
    reply = rig.cmd(line)
    assert reply.error is not None, line
    return str(reply.error)


def test_tsrm_p379_each_cs_has_its_own_forward_and_inverse_buffer_apart_from_the_progs(rig):
    """One forward and one inverse buffer per coordinate system (CS 1 ... 16), none shared
    with another CS's, the other kind's or a motion program's (PROG 1 ... 17 here)."""
    css, progs = (1, 2, 15, 16), (1, 2, 15, 16, 17)
    for cs in css:
        _enter(rig, f"&{cs} OPEN FORWARD", f"Q{cs}=1")
        _enter(rig, f"&{cs} OPEN INVERSE", f"P{cs}=2")
    for p in progs:
        _enter(rig, f"OPEN PROG {p}", f"P{100 + p}=3")
    for cs in css:
        assert rig.ok(f"&{cs} LIST FORWARD") == f"Q{cs}=1\rRET"
        assert rig.ok(f"&{cs} LIST INVERSE") == f"P{cs}=2\rRET"
    for p in progs:
        assert rig.ok(f"LIST PROG {p}") == f"P{100 + p}=3\rRET"


def test_tsrm_p379_open_forward_is_err007_while_the_rotary_buffer_is_open(rig):
    port = rig.c.open_port("host")
    rig.ok("&1 DEFINE ROT 100")
    rig.ok("&1 B0")
    rig.ok("OPEN ROT", port)
    assert "ERR007" in _err(rig, "&1 OPEN FORWARD")
    assert "ERR007" in _err(rig, "&1 OPEN INVERSE")


def test_tsrm_p270_undefine_all_names_the_first_running_cs(rig):
    """``UNDEFINE ALL`` while CS 1 and CS 2 both run a program: ERR001, and the message names
    CS 1, the lowest-numbered running CS ``[INF]``."""
    _enter(rig, "OPEN PROG 1", "LINEAR INC TA10 TS0 TM2000 X1")
    rig.ok("&1 #1->1000X")
    rig.ok("&2 #3->1000X")
    rig.ok("&1 B1 R")
    rig.ok("&2 B1 R")
    rig.run_for(0.1)
    for line, cs in (("UNDEFINE ALL", 1), ("&2 UNDEFINE", 2), ("&1 PMATCH", 1)):
        reply = rig.cmd(line)
        assert reply.error == "ERR001", line
        assert reply.detail is not None and f"CS {cs} is running" in reply.detail[1], line


def test_tsrm_p270_undefine_of_an_offset_axis_leaves_the_motor_where_it_is(rig):
    """``UNDEFINE`` commands no motion: a motor of an axis defined with an offset
    (``#1->1000X+500``) keeps its position when the definition goes."""
    rig.ok("&1 #1->1000X+500")
    rig.ok("#1J=2000")
    rig.run_until_idle(3)
    assert rig.ok("#1P") == "2000"
    rig.ok("&1 UNDEFINE")
    rig.run_for(0.2)
    assert rig.ok("#1P") == "2000"


def test_tsrm_p379_lines_added_to_a_forward_program_run_at_the_next_pmatch(rig):
    """``OPEN FORWARD`` without ``CLEAR`` adds lines after the stored ones (as for a PROG);
    the next ``PMATCH`` runs the longer program (TUM p267: PMATCH runs the forward program)."""
    rig.ok("&1 #1->I #2->I")
    for opener, lines in (("OPEN FORWARD", ["Q7=(P1+P2)/2000", "Q8=(P2-P1)/1000"]),
                          ("OPEN INVERSE", ["P1=(Q7-Q8/2)*1000", "P2=(Q7+Q8/2)*1000"])):
        rig.ok(f"&1 {opener} CLEAR")
        for line in lines:
            rig.ok(line)
        rig.ok("CLOSE")
    rig.ok("I5150=1")
    rig.ok("&1 PMATCH")
    assert rig.ok("&1 Q7 Q8") == "0\r0"
    rig.ok("&1 OPEN FORWARD")
    rig.ok("Q7=Q7+10")
    rig.ok("CLOSE")
    assert rig.ok("&1 LIST FORWARD").split("\r")[-2] == "Q7=Q7+10"
    rig.ok("&1 PMATCH")
    assert rig.ok("&1 Q7 Q8") == "10\r0"
    assert rig.c.positions(1) == {"X": 10.0, "Y": 0.0}  # the axes from Q7, Q8 (TUM p259)


def _forward_cs(rig, forward: list[str]) -> None:
    rig.ok("&1 #1->I #2->I")
    rig.ok("&1 OPEN FORWARD CLEAR")
    for line in forward:
        rig.ok(line)
    rig.ok("CLOSE")
    rig.ok("I5150=1")


def test_tum_p259_a_forward_program_with_gosub_returns_after_its_call(rig):
    """GOSUB / RETURN inside a kinematic program (the program's own N labels, PSRM p309):
    the lines after the GOSUB run once the subroutine returns."""
    _forward_cs(rig, ["Q8=1", "GOSUB100", "Q8=Q8+1", "RETURN", "N100 Q7=5", "RETURN"])
    rig.ok("&1 PMATCH")
    assert rig.ok("&1 Q7 Q8") == "5\r2"
    assert rig.c.positions(1) == {"X": 5.0, "Y": 2.0}


def test_tum_p259_a_forward_program_may_write_its_outputs_indirectly(rig):
    """``Q(Q20)`` / ``P(Q21)`` forms: the output written through an index counts as written."""
    _forward_cs(rig, ["Q20=7 Q21=30", "P(Q21)=4", "Q(Q20)=P30+1", "Q8=P(Q21)*2"])
    rig.ok("&1 PMATCH")
    assert rig.ok("&1 Q7 Q8") == "5\r8"
    assert rig.c.positions(1) == {"X": 5.0, "Y": 8.0}


@pytest.mark.parametrize(("extra", "fails"), [(0, False), (1, True)])
def test_a_forward_program_of_max_steps_statements_runs_and_one_more_fails(rig, extra, fails):
    """A kinematic run gives up after MAX_STEPS (5000) statements ``[INF]``: a straight
    program of exactly 5000 runs; one of 5001 is a ``kinematics`` failure event and leaves
    the axes unmatched."""
    add = " ".join(["Q20=Q20+1"] * 10)
    last = " ".join(["Q20=Q20+1"] * (7 + extra) + ["Q8=Q20"])
    _forward_cs(rig, ["Q7=1 Q20=0", *[add] * 499, last])
    assert MAX_STEPS == 5000
    rig.ok("&1 PMATCH")
    failures = [f for _, _, f in rig.events("kinematics") if f.get("error")]
    if fails:
        assert failures and "5001 statements" in failures[0]["error"]
        assert rig.c.positions(1) == {}
    else:
        assert failures == []
        assert rig.c.positions(1) == {"X": 1.0, "Y": 4997.0}


def test_tum_p259_a_goto_in_a_forward_program_does_not_return(rig):
    """GOTO jumps without a return address (PSRM GOTO / GOSUB): the RETURN after its target
    ends the program; the lines skipped never run."""
    _forward_cs(rig, ["Q8=1", "GOTO10", "Q8=99", "RETURN", "N10 Q7=5", "RETURN"])
    rig.ok("&1 PMATCH")
    assert rig.ok("&1 Q7 Q8") == "5\r1"


def test_tum_p258_each_kinematic_cs_drives_only_its_own_i_motors(rig):
    """CS 1 (#1->I) and CS 2 (#2->I) each with its own forward / inverse: a move in CS 2 runs
    CS 2's inverse for motor 2 alone; motor 1 of CS 1 stays, no kinematics error."""
    for cs, m in ((1, 1), (2, 2)):
        rig.ok(f"&{cs} #{m}->I")
        for opener, line in (("OPEN FORWARD", f"Q7=P{m}/1000"), ("OPEN INVERSE", f"P{m}=Q7*1000")):
            rig.ok(f"&{cs} {opener} CLEAR")
            rig.ok(line)
            rig.ok("CLOSE")
        rig.ok(f"I5{cs}50=1 I5{cs}13=10")
    rig.ok("OPEN PROG 1 CLEAR")
    rig.ok("LINEAR ABS TA50 TS0 TM200 X1")
    rig.ok("CLOSE")
    rig.ok("&2 B1 R")
    rig.run_until_idle()
    assert [f for _, _, f in rig.events("kinematics") if f.get("error")] == []
    assert rig.ok("#2P #1P").split("\r") == ["1000", "0"]
