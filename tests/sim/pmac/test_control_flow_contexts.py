"""The same control-flow texts fed to every entry point, one answer per context (issue 31
item 1): a PLC (``OPEN PLC``), a fixed motion program (``OPEN PROG``), a kinematic program
(``OPEN FORWARD``, entered and run as a PROG is) and the rotary buffer (``OPEN ROT``).

One parser (the keyword table) reads them all; the contexts differ only where the manuals
say so:

* **one-line forms** (``IF (c) {statements}``, ``ELSE {statements}``, ``WHILE (c)
  {action}``) are motion-program forms: "no ENDIF or ENDWHILE is required ... and none may be
  used" (PUM p162 "Single-Line Condition Actions"; PSRM p313 ELSE, p357 WHILE). In a PLC the
  statements after the condition belong to the block and an ``ENDIF`` / ``ENDWHILE`` must
  close it (PSRM p313: the card "puts the statements on the next program line and expects
  an ENDIF");
* **multi-line conditions** (a line starting ``AND (...)`` / ``OR (...)``) are for PLCs only
  (PUM p162 "Multiple-Line Conditions"); elsewhere the line is not a command (ERR003);
* a **structural error** (``ENDIF`` / ``ELSE`` / ``ENDWHILE`` with nothing open, a one-line
  form closed by ``ENDIF``) is ERR009, "program structural error", in PLCs and programs
  alike (PSRM p25-26, the I6 error table);
* the **rotary buffer** takes no multi-line control flow: "single-line condition actions are
  the only types of conditional statements permitted" (PUM p162), as the line to jump to
  may not be in the buffer yet;
* blanks are not significant (TSRM p23): ``IF(P174!=0ANDP176!=0)`` is two conditions.

Before this table: ``ENDIF`` alone was ERR003 in a PLC and ERR009 in a PROG; ``WHILE (P1=0)
ENDW`` and ``IF (P1=0) P2=1 ENDIF`` were accepted in a PLC as one-line blocks; a PLC's
``IF (c) P2=1`` ended with its line.
"""

from __future__ import annotations

import pytest

from .conftest import Rig

OPEN = {
    "PLC": "OPEN PLC 1 CLEAR",
    "PROG": "OPEN PROG 1 CLEAR",
    "FORWARD": "&1 OPEN FORWARD CLEAR",
    "ROT": "OPEN ROT",
}
OK = None

#: (lines, {context: None = accepted through CLOSE, or "ERRnnn@k": line k answers it}).
TABLE = [
    (["ENDIF"], dict(PLC="ERR009@1", PROG="ERR009@1", FORWARD="ERR009@1", ROT="ERR003@1")),
    (["ELSE"], dict(PLC="ERR009@1", PROG="ERR009@1", FORWARD="ERR009@1", ROT="ERR003@1")),
    (["ENDWHILE"], dict(PLC="ERR009@1", PROG="ERR009@1", FORWARD="ERR009@1",
                        ROT="ERR003@1")),
    # a block closed on its own line: a PLC block; in a program a one-line form with an ENDW
    (["WHILE (P1=0) ENDW"], dict(PLC=OK, PROG="ERR009@1", FORWARD="ERR009@1",
                                 ROT="ERR003@1")),
    (["IF (P1=0) P2=1 ENDIF"], dict(PLC=OK, PROG="ERR009@1", FORWARD="ERR009@1",
                                    ROT="ERR003@1")),
    # the one-line IF: a program form; in a PLC the IF is still open at CLOSE (line 2)
    (["IF (P1=0) P2=1"], dict(PLC="ERR009@2", PROG=OK, FORWARD=OK)),
    (["IF (P1=1) P2=1", "ELSE P2=2"], dict(PLC="ERR009@3", PROG=OK, FORWARD=OK)),
    (["IF (P1=1)", "P2=1", "ELSE", "P2=2", "ENDIF"],
     dict(PLC=OK, PROG=OK, FORWARD=OK, ROT="ERR003@1")),
    (["WHILE (P1=0)", "ENDWHILE"], dict(PLC=OK, PROG=OK, FORWARD=OK, ROT="ERR003@1")),
    (["IF (P1=1)", "AND (P2=1)", "P3=1", "ENDIF"],
     dict(PLC=OK, PROG="ERR003@2", FORWARD="ERR003@2", ROT="ERR003@1")),
    (["WHILE (P1=1)", "OR (P2=1)", "ENDW"],
     dict(PLC=OK, PROG="ERR003@2", FORWARD="ERR003@2", ROT="ERR003@1")),
    (["IF(P174!=0ANDP176!=0)", "P1=1", "ENDIF"],
     dict(PLC=OK, PROG=OK, FORWARD=OK, ROT="ERR003@1")),
    (["IF ((P1>-20) AND (P1<20))", "ENDIF"],  # TUM p252: illegal parentheses
     dict(PLC="ERR003@1", PROG="ERR003@1", FORWARD="ERR003@1", ROT="ERR003@1")),
]


def _enter(context: str, lines: list[str]) -> str | None:
    rig = Rig()
    rig.rotary_setup()
    rig.ok("&1 #1->X")
    rig.ok(OPEN[context])
    for k, line in enumerate([*lines, "CLOSE"], start=1):
        reply = rig.cmd(line)
        if reply.error is not None:
            return f"{reply.error}@{k}"
    return None


@pytest.mark.parametrize(("lines", "context", "want"), [
    (lines, context, want) for lines, answers in TABLE for context, want in answers.items()
], ids=lambda v: "|".join(v) if isinstance(v, list) else str(v))
def test_one_answer_per_text_and_context(lines, context, want):
    assert _enter(context, lines) == want


def test_a_refused_line_stores_nothing():
    rig = Rig()
    rig.ok("OPEN PLC 2 CLEAR")
    rig.ok("P1=1")
    assert rig.cmd("ENDIF").error == "ERR009"
    rig.ok("CLOSE")
    assert rig.c.plcs.plc(2).program.lines == ("P1=1",)
    rig.ok("OPEN PROG 2 CLEAR")
    rig.ok("P1=1")
    assert rig.cmd("ENDIF").error == "ERR009"
    rig.ok("CLOSE")
    assert rig.c.program_lines(2) == ["P1=1"]


# -- one compiled form (issue 31 item 1) ------------------------------------------------------

STRUCTURED = [
    ["IF (P1=1)", "P2=1", "ELSE", "P2=2", "ENDIF"],
    ["WHILE (P1<10)", "P1=P1+1", "ENDWHILE", "P3=1"],
    ["IF (P1=1)", "WHILE (P2<3)", "P2=P2+1", "ENDWHILE", "ELSE", "IF (P4=0)", "P4=1", "ENDIF",
     "ENDIF"],
]


def _skeleton(instrs):
    """Kinds and jump targets of compiled instructions; a statement (a PLC leaf or a
    program's line chunk) counts as ``S``."""
    from motionsim.sim.pmac.buffers import flow

    names = {flow.I_IF: "IF", flow.I_WHILE: "WHILE", flow.I_JUMP: "JUMP"}
    out = []
    for i in instrs:
        kind = names.get(i[0], "S")
        out.append((kind, i[3] if kind in ("IF", "WHILE") else tuple(i[2:4]) if kind == "JUMP"
                    else None))
    return out


@pytest.mark.parametrize("lines", STRUCTURED, ids=lambda v: "|".join(v))
def test_a_plc_and_a_program_compile_the_same_text_to_the_same_structure(lines):
    """A PLC and a motion program build their control flow in one structure
    (``buffers/flow.py``): for a text both contexts accept, one statement per line, the
    instructions and every jump target are the same; only the leaves differ (a PLC
    statement, a program line chunk)."""
    from motionsim.sim.pmac import compile_plc
    from motionsim.sim.pmac.buffers import flow
    from motionsim.sim.pmac.buffers.program import compile_statements
    from motionsim.sim.pmac.language.parser import parse_program_line

    plc = compile_plc("\n".join(lines))
    code, problem = flow.build([compile_statements(t, parse_program_line(t)) for t in lines])
    assert problem is None
    assert _skeleton(plc.ops) == _skeleton(code.instrs)
    assert any(k == "JUMP" for k, _ in _skeleton(plc.ops))


def test_a_plc_scan_ends_at_the_jump_back_of_its_endwhile():
    """The PLC's own stop rule on the shared code: a scan ends at ENDWHILE's jump back
    (the next scan resumes at the WHILE, seed 003), so ``P1`` counts one per scan."""
    rig = Rig()
    rig.ok("OPEN PLC 3 CLEAR")
    for line in ("WHILE (P1<5)", "P1=P1+1", "ENDWHILE", "P2=1"):
        rig.ok(line)
    rig.ok("CLOSE")
    plcs = rig.c.plcs
    plc = plcs.plc(3)
    counts = []
    for _ in range(7):
        plcs.scan(plc)
        counts.append((rig.c.vars.read("P", 1), rig.c.vars.read("P", 2)))
    assert counts == [(1, 0), (2, 0), (3, 0), (4, 0), (5, 0), (5, 1), (5, 1)]
