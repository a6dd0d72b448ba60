"""PLC programs: entry (OPEN PLC / CLEAR / CLOSE), ENABLE / DISABLE, what one scan does.

Seed 003 and spec §9.5: a background scan runs to the end or to an ENDWHILE; PLC 0 runs in
the RTI; I5 (Turbo default 1) permits the classes. Times in servo cycles (``rig.cyc``).
"""

from __future__ import annotations

import pytest
from motionsim.sim.errors import Conflict, ParseError


def enter(rig, *lines: str, n: int = 1) -> None:
    rig.ok(f"OPEN PLC {n} CLEAR")
    for line in lines:
        rig.ok(line)
    rig.ok("CLOSE")


def mvals(rig, name: str) -> list[float]:
    return [f["value"] for _, _, f in rig.events("mvar") if f["name"] == name]


def test_open_plc_clear_lines_close_stores_the_program(rig):
    enter(rig, "P1=P1+1", "IF (P1>2)", "P2=7", "ENDIF")
    (plc,) = rig.c.plcs.to_list()
    assert (plc["plc"], plc["lines"], plc["state"], plc["scans"]) == (1, 4, "disabled", 0)


def test_enable_and_disable_emit_plc_events(rig):
    enter(rig, "P1=1", n=1)
    enter(rig, "P1=1", n=2)
    rig.ok("ENABLE PLC 1,2")
    rig.ok("DISABLE PLC 1..2")
    got = [(f["plc"], f["state"]) for _, _, f in rig.events("plc")]
    assert got == [(1, "enabled"), (2, "enabled"), (1, "disabled"), (2, "disabled")]


def test_i5_default_1_runs_plc0_but_not_background_plcs(rig):
    """TSRM p39: I5=1 (Turbo default) — foreground PLCs on, background PLCs off."""
    enter(rig, "M1=M1+1", n=1)
    enter(rig, "M2=M2+1", n=0)
    rig.ok("ENABLE PLC 0 ENABLE PLC 1")
    rig.run_for(0.1)
    assert mvals(rig, "M1") == [] and len(mvals(rig, "M2")) > 50
    rig.ok("I5=2")
    rig.run_for(0.1)
    n2 = len(mvals(rig, "M2"))
    assert len(mvals(rig, "M1")) > 100
    rig.run_for(0.1)
    assert len(mvals(rig, "M2")) == n2  # I5=2: foreground PLCs off


def test_a_scan_stops_at_endwhile_and_resumes_at_the_while(rig):
    """Seed 003: one scan runs to the end or to an ENDWHILE; WHILE waits without blocking."""
    rig.ok("I5=3")
    enter(rig, "M1=1", "WHILE (P5=0)", "M3=M3+1", "ENDWHILE", "M1=2")
    rig.ok("ENABLE PLC 1")
    rig.run_for(0.01)
    assert mvals(rig, "M1") == [1]
    loops = len(mvals(rig, "M3"))
    assert loops > 10  # one pass of the loop body per scan
    rig.ok("P5=1")
    rig.run_for(0.01)
    # The loop ends; the scan goes on to the end, then starts again at the top.
    assert mvals(rig, "M1")[:3] == [1, 2, 1]


def test_if_else_endif(rig):
    enter(rig, "IF (P1=1 AND P2!<3)", "M1=10", "ELSE", "M1=20", "ENDIF", n=0)
    rig.ok("P1=1 P2=3 ENABLE PLC 0")
    rig.run_for(0.003)
    rig.ok("P2=2")
    rig.run_for(0.003)
    vals = mvals(rig, "M1")
    assert vals[0] == 10 and vals[-1] == 20


def test_statements_after_a_plc_if_belong_to_its_block_until_endif(rig):
    """PLCs have no one-line IF (PUM p162 "Single-Line Condition Actions": motion programs
    only; PSRM p313: in a PLC the card puts the statements on the next program line and
    expects an ENDIF). This test pinned the old one-line reading (the block ended with its
    line): the manual decides."""
    enter(rig, "IF (P1>0) M1=1", "M2=1", "ENDIF", "M3=1", n=0)
    rig.ok("ENABLE PLC 0")
    rig.run_for(0.003)
    assert mvals(rig, "M1") == [] and mvals(rig, "M2") == [] and mvals(rig, "M3")
    rig.ok("OPEN PLC 1 CLEAR")
    rig.ok("IF (P1>0) M1=1")
    rig.ok("M2=1")
    assert rig.cmd("CLOSE").error == "ERR009"  # the IF is still open
    rig.ok("ENDIF CLOSE")


def test_plc_cmd_starts_a_rotary_program(rig):
    """TSRM p422: CMD"..." queues an on-line command; CMD"&1B0R" runs the rotary program."""
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM10 X1", "X2"])
    enter(rig, "IF (P1=1)", 'CMD"&1B0R"', "P1=0", "ENDIF", n=0)
    rig.ok("ENABLE PLC 0")
    rig.run_for(0.01)
    assert rig.events("program") == []
    rig.ok("P1=1")
    t_set = rig.c.now
    rig.run_for(0.5)
    prog = rig.events("program")
    assert prog[0][1:] == ("program", {"cs": 1, "state": "running"})
    assert prog[0][0] > rig.cyc(t_set)
    assert [f["n"] for _, _, f in rig.events("move_end")] == [1, 2]
    assert rig.c.get_variable("P1") == 0  # cleared in the same scan: issued once


def test_plc_cmd_addressing_is_not_modal(rig):
    """TSRM p422: every PLC command starts addressing motor 1 / CS 1."""
    enter(rig, 'CMD"&2Q1=5"', 'CMD"Q2=6"', "DISABLE PLC 0", n=0)
    rig.ok("ENABLE PLC 0")
    rig.run_for(0.01)
    assert rig.ok("&2 Q1 Q2") == "5\r0"
    assert rig.ok("&1 Q2") == "6"


def test_send_records_the_message(rig):
    enter(rig, 'SEND"HELLO"', "DISABLE PLC 0", n=0)
    rig.ok("ENABLE PLC 0")
    rig.run_for(0.01)
    (plc,) = rig.c.plcs.to_list()
    assert plc["last_send"] == "HELLO" and plc["scans"] == 1 and plc["state"] == "disabled"


def test_a_malformed_line_answers_err003_and_is_not_stored(rig):
    rig.ok("OPEN PLC 3 CLEAR")
    rig.ok("P1=1")
    assert rig.cmd("IF (P1>>2)").error == "ERR003"
    assert rig.cmd("X10").error == "ERR003"  # motion statements belong to motion programs
    # no IF to close: ERR009, "program structural error" (PSRM p25-26, I6 table), as in a
    # PROG; this line pinned ERR003 before the PLC and motion-program rules were one
    assert rig.cmd("ENDIF").error == "ERR009"
    rig.ok("CLOSE")
    (plc,) = rig.c.plcs.to_list()
    assert plc["lines"] == 1


def test_close_with_an_open_if_is_a_structural_error_and_keeps_the_buffer_open(rig):
    enter(rig, "P1=1", n=4)
    rig.ok("OPEN PLC 4 CLEAR")
    rig.ok("IF (P1=1)")
    assert rig.cmd("CLOSE").error == "ERR009"
    assert rig.c.plcs.editing() == 4
    rig.ok("ENDIF CLOSE")
    assert rig.c.plcs.editing() is None


def test_reopening_keeps_the_program_until_clear(rig):
    enter(rig, "P1=1", "P2=2", n=5)
    rig.ok("OPEN PLC 5")
    rig.ok("P3=3")
    rig.ok("CLOSE")
    assert rig.c.plcs.plc(5).program.lines == ("P1=1", "P2=2", "P3=3")


def test_open_plc_while_another_buffer_is_open_is_err007(rig):
    rig.rotary_setup()
    rig.ok("OPEN ROT")
    assert rig.cmd("OPEN PLC 1").error == "ERR007"
    rig.ok("CLOSE")
    other = rig.c.open_port("tcp")
    rig.ok("OPEN PLC 1")
    assert rig.cmd("OPEN ROT", other).error == "ERR007"
    assert rig.cmd("OPEN PLC 2", other).error == "ERR007"


def test_enabling_an_empty_plc_is_accepted_and_changes_nothing(rig):
    rig.ok("ENABLE PLC 7")
    assert rig.events("plc") == [] and rig.c.plcs.to_list() == []


def test_open_plc_disables_the_plc_being_edited(rig):
    enter(rig, "M1=M1+1", n=0)
    rig.ok("ENABLE PLC 0")
    rig.ok("OPEN PLC 0")
    rig.ok("CLOSE")
    assert [f["state"] for _, _, f in rig.events("plc")] == ["enabled", "disabled"]


def test_load_replaces_a_program_whole_or_raises_with_line_and_column(rig):
    plcs = rig.c.plcs
    plcs.load(2, "P1=1\nIF (P1=1)\nP2=2\nENDIF")
    with pytest.raises(ParseError) as e:
        plcs.load(2, "P1=1\nIF (P1=>1)\nENDIF")
    assert (e.value.line, e.value.column, e.value.pmac_error) == (2, 8, "ERR003")
    with pytest.raises(ParseError) as e:
        plcs.load(2, "WHILE (P1=1)\nP2=2")
    assert e.value.pmac_error == "ERR009"
    assert plcs.plc(2).program.lines == ("P1=1", "IF (P1=1)", "P2=2", "ENDIF")
    rig.ok("OPEN PLC 2")
    with pytest.raises(Conflict):
        plcs.load(2, "P1=1")


def test_reset_erases_plcs(rig):
    enter(rig, "M1=M1+1", n=0)
    rig.ok("ENABLE PLC 0")
    rig.c.reset()
    n = len(mvals(rig, "M1"))
    rig.run_for(0.1)
    assert len(mvals(rig, "M1")) == n and rig.c.plcs.to_list() == []


def test_a_startup_plc_enables_another_and_disables_itself(rig):
    """The usual start-up pattern: PLC 1 runs once, enables PLC 2, disables itself."""
    rig.ok("I5=3")
    rig.c.plcs.load(2, "M2=M2+1")
    enter(rig, "M1=1 ENABLE PLC 2 DISABLE PLC 1 P9=1", n=1)
    rig.ok("ENABLE PLC 1")
    rig.run_for(0.01)
    got = [(f["plc"], f["state"]) for _, _, f in rig.events("plc")]
    assert got == [(1, "enabled"), (2, "enabled"), (1, "disabled")]
    assert mvals(rig, "M1") == [1] and len(mvals(rig, "M2")) > 5
    assert rig.c.get_variable("P9") == 1  # the scan runs to its end after its own DISABLE


def test_a_multi_line_condition_with_and_or_lines(rig):
    """TUM p253: in PLCs a condition may continue on ``AND (...)`` / ``OR (...)`` lines."""
    enter(rig, "IF (P1=1)", "AND (P2=1)", "OR (P3=1)", "M1=1", "ELSE", "M1=2", "ENDIF", n=0)
    rig.ok("ENABLE PLC 0")
    seen = []
    for p1, p2, p3 in [(1, 1, 0), (1, 0, 0), (0, 0, 1), (0, 1, 0)]:
        rig.ok(f"P1={p1} P2={p2} P3={p3}")
        rig.run_for(0.005)
        seen.append(rig.c.get_variable("M1"))
    assert seen == [1, 2, 1, 2]


def test_an_and_line_must_follow_an_if_or_while(rig):
    rig.ok("OPEN PLC 1 CLEAR")
    rig.ok("P1=1")
    assert rig.cmd("AND (P2=1)").error == "ERR003"
    rig.ok("CLOSE")


def test_background_plc_cmd_is_queued_to_the_command_interpreter(make_rig):
    """TSRM p423-424: a CMD"..." from a background PLC is queued to the background command
    interpreter like a host command; the scan that issued it ends first, and the command runs
    at the end of that background cycle (the PLC clears its trigger so it is issued once)."""
    rig = make_rig(i5=2)
    enter(rig, "IF (P1=0)", 'CMD"P5=P5+1"', "P1=1", "ENDIF", n=1)
    rig.ok("ENABLE PLC 1")
    rig.run_for(0.01)
    assert rig.c.get_variable("P5") == 1
    assert rig.c.get_variable("P1") == 1
    (plc,) = rig.c.plcs.to_list()
    assert plc["scans"] > 1


def test_background_plc_cmd_every_scan_runs_one_command_per_cycle(make_rig):
    """A background PLC that issues CMD"..." on every scan: each command is queued during the
    scan and run at the end of that background cycle, so the count of commands run follows
    the count of scans (the last one may still be queued) — no scan re-enters another."""
    rig = make_rig(i5=2)
    enter(rig, 'CMD"P5=P5+1"', n=1)
    rig.ok("ENABLE PLC 1")
    rig.run_for(0.01)
    (plc,) = rig.c.plcs.to_list()
    assert plc["scans"] >= 10
    assert plc["scans"] - 1 <= rig.c.get_variable("P5") <= plc["scans"]
