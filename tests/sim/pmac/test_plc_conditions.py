"""PLC conditions as the manuals and real programs write them (issue 37 item 3).

* ``IF (a) AND (b)`` / ``OR (b)`` on one line, and continuation lines starting ``AND (`` /
  ``OR (`` (PUM p162 "Multiple-Line Conditions": PLCs only; AND binds tighter than OR, TUM
  p252), a continuation's expression may itself start with a parenthesis;
* several statements on one line (TSRM p259: a line is read left to right);
* no blanks between tokens (TSRM p23: blanks are not significant): ``IF(P174!=0ANDP176!=0)``
  and the card's own ``LIST PLC`` output, which runs the same when entered again;
* blanks inside words where they do not matter: ``END GATHER``, ``END Gat`` are
  ``ENDGATHER`` (tests/sim/pmac/test_data_gathering.py).
"""

from __future__ import annotations

import pytest

from .conftest import Rig


def _enter(rig: Rig, n: int, *lines: str) -> None:
    rig.ok("I5=3")  # foreground and background PLCs may run (TSRM I5)
    rig.ok(f"OPEN PLC {n} CLEAR")
    for line in lines:
        rig.ok(line)
    rig.ok("CLOSE")


def _scan(rig: Rig, n: int, **p: float) -> float:
    """Set the P-variables, run PLC ``n`` once (enabled for a few ms) and read P10."""
    rig.ok("P10=0 " + " ".join(f"{k}={v}" for k, v in p.items()))
    rig.ok(f"ENABLE PLC {n}")
    scans = rig.c.plcs.plc(n).scans
    rig.run_for(0.01)
    rig.ok(f"DISABLE PLC {n}")
    assert rig.c.plcs.plc(n).scans > scans
    return float(rig.ok("P10"))


#: (P1, P2, P3) -> whether ``(P1=1 AND P2=1) OR P3=1`` holds.
TRUTH = [((a, b, c), bool((a and b) or c)) for a in (0, 1) for b in (0, 1) for c in (0, 1)]


@pytest.mark.parametrize("lines", [
    ("IF (P1=1) AND (P2=1) OR (P3=1)", "P10=1", "ENDIF"),
    ("IF (P1=1)", "AND (P2=1)", "OR (P3=1)", "P10=1", "ENDIF"),
    ("IF (P1=1 AND P2=1)", "OR (P3=1)", "P10=1", "ENDIF"),
    ("IF(P1=1)AND(P2=1)OR(P3=1)", "P10=1", "ENDI"),
    ("IF (P1=1)", "AND ((P2+P3-P3)*2=2)", "OR ((P3)=1)", "P10=1", "ENDIF"),
    ("IF (P1=1) AND (P2=1)", "OR (P3=1)", "P10=1", "ENDIF"),
], ids=["one line", "continuation lines", "compound then OR line", "no blanks",
        "continuation starting with a parenthesis", "one line then OR line"])
def test_and_binds_tighter_than_or_on_one_line_and_over_lines(lines):
    rig = Rig()
    _enter(rig, 1, *lines)
    got = [(p, _scan(rig, 1, P1=p[0], P2=p[1], P3=p[2]) == 1) for p, _ in TRUTH]
    assert got == TRUTH


def test_several_statements_on_one_line_and_no_blanks_between_tokens():
    rig = Rig()
    _enter(rig, 2, "P20=0 P21=2 IF(P174!=0ANDP176!=0)P10=P21+1 ENDIF P22=P22+1")
    assert _scan(rig, 2, P174=1, P176=2) == 3
    assert _scan(rig, 2, P174=1, P176=0) == 0
    assert float(rig.ok("P22")) >= 2  # after the ENDIF: every scan


def test_the_cards_own_listing_entered_again_runs_the_same():
    """LIST PLC answers the program without blanks and with short keywords (spec §11.8);
    a host that saves it and sends it back must get the same program."""
    rig = Rig()
    source = ("IF (P1=1)", "AND (P2=1)", "OR (P3=1)", "P10=1", "ELSE", "P10=2", "ENDIF",
              "ENABLE PLC 5", "ADDRESS&2 CMD\"#1J+\"")
    _enter(rig, 3, *source)
    listed = rig.ok("LIST PLC 3").split("\r")
    assert listed[-1] == "RET" and "IF(P1=1)" in listed[0]
    _enter(rig, 4, *listed[:-1])
    assert rig.ok("LIST PLC 4") == rig.ok("LIST PLC 3")
    for p, _ in TRUTH:
        args = dict(P1=p[0], P2=p[1], P3=p[2])
        assert _scan(rig, 3, **args) == _scan(rig, 4, **args)


def test_a_continuation_line_must_start_its_line_and_follow_an_if_or_while():
    rig = Rig()
    rig.ok("OPEN PLC 6 CLEAR")
    assert rig.cmd("AND (P1=1)").error == "ERR003"  # nothing above it to extend
    rig.ok("IF (P1=1)")
    assert rig.cmd("P2=1 AND (P1=1)").error == "ERR003"  # AND in the middle of a line
    rig.ok("AND (P2=1)")
    rig.ok("ENDIF")
    rig.ok("CLOSE")
    assert rig.ok("LIST PLC 6").split("\r")[:3] == ["IF(P1=1)", "AND(P2=1)", "ENDI"]
