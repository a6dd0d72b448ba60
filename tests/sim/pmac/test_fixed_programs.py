"""Fixed motion programs: OPEN PROG / CLEAR / CLOSE, ``&c B n R``, through the rotary
program's interpreter and lookahead (TSRM p381, p295; spec pmac.md §11.8)."""

from __future__ import annotations

import pytest

PROG = ["TM100 TA10 TS0", "X10", "X20", "X30"]


def load(rig, n: int = 1, lines=PROG) -> None:
    rig.ok(f"OPEN PROG {n} CLEAR")
    for line in lines:
        rig.ok(line)
    rig.ok("CLOSE")


def test_a_fixed_program_runs_its_moves_and_stops_at_its_end(rig):
    load(rig)
    rig.ok("&1 B1 R")
    rig.run_until_idle()
    starts = [e["n"] for _, _, e in rig.events("move_start")]
    assert starts == [2, 3, 4]
    states = [e["state"] for _, _, e in rig.events("program")]
    assert states == ["running", "stopped"]  # a rotary program would be "waiting"
    assert rig.c.positions(1)["X"] == pytest.approx(30.0)
    assert rig.c.coord(1)["program"] == {"state": "stopped"}
    assert not int(rig.ok("&1??")[:6], 16) & 1  # word 1 bit 0: not running


def test_same_program_timing_as_the_rotary_buffer(make_rig):
    """The same lines give the same move events, at the same servo cycles, from PROG 1 and
    from the rotary buffer (one interpreter, one lookahead)."""
    fixed = make_rig()
    load(fixed)
    fixed.ok("&1 B1 R")
    fixed.run_until_idle()
    rot = make_rig()
    rot.rotary_setup()
    rot.ok("OPEN ROT")
    for line in PROG:
        rot.ok(line)
    rot.ok("CLOSE")
    rot.ok("&1 R")
    rot.run_until_idle()
    f = fixed.events("move_start", "move_end")
    r = rot.events("move_start", "move_end")
    assert [(k - f[0][0], t, e["n"]) for k, t, e in f] == [
        (k - r[0][0], t, e["n"]) for k, t, e in r
    ]
    assert len(f) == 6


def test_r_after_the_end_runs_the_program_again_from_the_top(rig):
    load(rig, 7, ["TM50", "X5", "X0"])
    rig.ok("&2 B7 R")
    rig.run_until_idle()
    rig.ok("&2 R")
    rig.run_until_idle()
    assert [e["n"] for _, _, e in rig.events("move_start")] == [2, 3, 2, 3]


def test_open_prog_rules_err007_err001_err015(rig):
    load(rig)
    rig.ok("&1 B1 R")
    assert rig.cmd("OPEN PROG 2").error == "ERR001"  # a CS runs a program
    rig.run_until_idle()
    rig.ok("OPEN PROG 2")
    assert rig.cmd("OPEN ROT").error == "ERR007"  # a buffer is open
    assert rig.cmd("OPEN PROG 3").error == "ERR007"
    assert rig.cmd("&1 R").error == "ERR015"  # no CS may run while a PROG is open
    rig.ok("CLOSE")
    assert rig.cmd("&1 R").error == "ERR015"  # every CS must be pointed again with B
    rig.ok("&1 B1 R")


def test_lines_of_an_open_prog_are_stored_not_executed_and_clear_empties_it(rig):
    rig.ok("OPEN PROG 5")
    rig.ok("P1=7 X100")
    rig.ok("CLEAR")
    rig.ok("X1")
    rig.ok("CLOSE")
    assert rig.ok("P1") == "0"
    assert [line.text for line in rig.c.programs.programs[5]] == ["X1"]
    assert rig.events("line_loaded") == []  # nothing went into a rotary buffer


def test_a_bad_line_in_an_open_prog_is_refused_and_stores_nothing(rig):
    rig.ok("OPEN PROG 1")
    assert rig.cmd("X(1+").error == "ERR003"
    rig.ok("CLOSE")
    assert rig.c.programs.programs[1] == []


def test_running_a_missing_program_answers_err015(rig):
    assert rig.cmd("&1 B9 R").error == "ERR015"
    assert rig.events("program") == []


def test_list_prog_answers_the_program_as_the_card_lists_it(rig):
    """Spec §11.8: decompiled lines (blanks and comments dropped), ``RET`` added; with
    ``,start,len`` as ``offset:text``; a missing program is ERR003."""
    load(rig, 3, ["TM100 TA10 TS0", "X10 ; first", "X20"])
    assert rig.ok("LIST PROG 3").split("\r") == ["TM100TA10TS0", "X10", "X20", "RET"]
    assert rig.ok("LIST PROG 3,0,80").split("\r") == ["0:TM100TA10TS0", "3:X10", "4:X20",
                                                      "5:RET"]
    assert rig.cmd("LIST PROG 4").error == "ERR003"
