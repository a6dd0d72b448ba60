"""One-line IF forms (PSRM p313: ``IF (c) {statements}`` ends with its line) deep in a long
program and inside an open WHILE block: entry is accepted and the program runs them.
Virtual time."""

from __future__ import annotations


def _enter(rig, n: int, lines: list[str]) -> None:
    rig.ok(f"OPEN PROG {n} CLEAR")
    for line in lines:
        rig.ok(line)
    reply = rig.cmd("CLOSE")
    assert (reply.error, reply.detail) == (None, None)


def test_psrm_p313_a_one_line_if_on_line_300_ends_with_its_line(rig):
    _enter(rig, 1, [f"P{n + 1}={n}" for n in range(299)] + ["IF (P1=0) P500=7", "P501=1"])
    rig.ok("&1 B1 R")
    rig.run_for(1.0)
    assert rig.ok("P500 P501").split("\r") == ["7", "1"]


def test_psrm_p313_a_one_line_if_inside_a_while_block_ends_with_its_line(rig):
    _enter(rig, 2, ["P1=0", "WHILE (P1<3)", "IF (P1=1) P10=P10+1", "P1=P1+1", "ENDWHILE",
                    "P2=5"])
    rig.ok("&1 B2 R")
    rig.run_for(1.0)
    assert rig.ok("P1 P2 P10").split("\r") == ["3", "5", "1"]
