"""Keyword spellings written out by hand, so that a row dropped from the keyword table
(``sim/pmac/language/keywords.py``) fails a test.

``test_keyword_table.py`` is parametrized from the table itself: it proves every row's
spellings parse, but a row (or a spelling) removed from the table simply disappears from its
cases. The lists below are typed from the Turbo PMAC Software Reference Manual's command
descriptions (TSRM on-line commands p260-420, program commands p425-480; the short forms as
the manual heads each command, e.g. "ENDWHILE / ENDW", "ENABLE PLC / ENA PLC", "ADDRESS /
ADR", "COMMAND / CMD") and from Diamond's public programs (spec pmac.md §12.1: ``ENDW``,
``ENDI``, ``RET``, ``ENA``, ``DIS``, ``CMD``, ``DEF``, ``DEL``, ``ROT``, ``GAT``, ``INV``).
TSRM p23: blanks are not significant, so ``ENAPLC3`` is ``ENA PLC 3``. Each entry names the
statement the card builds, which the parser must return whatever the table looks like.
"""

from __future__ import annotations

import pytest
from motionsim.sim.errors import ParseError
from motionsim.sim.pmac.language.parser import parse_line

#: (text as written, written with a buffer open, statement class built)
SIMULATED: list[tuple[str, bool, str]] = [
    # buffer management (TSRM on-line commands)
    ("OPEN PROG 3", False, "OpenProgram"), ("OPEN PROGRAM 3", False, "OpenProgram"),
    ("OPEN ROT", False, "OpenRotary"), ("OPEN ROTARY", False, "OpenRotary"),
    ("OPEN PLC 3", False, "OpenPlc"),
    ("OPEN FORWARD", False, "OpenKinematic"), ("OPEN FWD", False, "OpenKinematic"),
    ("OPEN INVERSE", False, "OpenKinematic"), ("OPEN INV", False, "OpenKinematic"),
    ("CLOSE", False, "Close"),
    ("DEFINE GATHER", False, "DefineGather"), ("DEF GAT", False, "DefineGather"),
    ("DELETE GATHER", False, "DeleteGather"), ("DEL GAT", False, "DeleteGather"),
    ("GATHER", False, "Gather"), ("GAT", False, "Gather"),
    ("ENDGATHER", False, "EndGather"), ("ENDG", False, "EndGather"),
    ("END GATHER", False, "EndGather"),
    ("ENABLE PLC 3", False, "EnablePlc"), ("ENA PLC 3", False, "EnablePlc"),
    ("ENAPLC3", False, "EnablePlc"), ("ENABLE PLCC 3", False, "EnablePlc"),
    ("ENAPLCC3", False, "EnablePlc"),
    ("DISABLE PLC 3", False, "EnablePlc"), ("DIS PLC 3..5", False, "EnablePlc"),
    ("DISPLC3", False, "EnablePlc"),
    ("VERSION", False, "Query"), ("VER", False, "Query"), ("PMATCH", False, "Pmatch"),
    ("I5=2", False, "Assign"),
    # motion-program and PLC statements (TSRM program commands)
    ("ENDWHILE", True, "EndWhile"), ("END WHILE", True, "EndWhile"),
    ("ENDW", True, "EndWhile"),
    ("ENDIF", True, "EndIf"), ("END IF", True, "EndIf"), ("ENDI", True, "EndIf"),
    ("RETURN", True, "Return"), ("RET", True, "Return"),
    ("DWELL100", True, "Dwell"), ("DWE100", True, "Dwell"),
    ("DELAY100", True, "Delay"), ("DLY100", True, "Delay"),
    ("LINEAR X1", True, "MoveMode"), ("LIN X1", True, "MoveMode"),
    ("RAPID X1", True, "MoveMode"), ("RPD X1", True, "MoveMode"),
    ("CIRCLE1", True, "MoveMode"), ("CIR1", True, "MoveMode"),
    ("ADDRESS&2", True, "Address"), ("ADR&2", True, "Address"),
    ('COMMAND"#1J+"', True, "Message"), ('CMD"#1J+"', True, "Message"),
    ('CMDS"#1J+"', True, "Message"), ('CMDP"#1J+"', True, "Message"),
    ('SEND"HI"', True, "Message"), ('SENDS"HI"', True, "Message"),
    ('SENDP"HI"', True, "Message"),
    ("WAIT", True, "Wait"),
]

#: Valid Turbo PMAC words motionsim does not simulate: answered ``not_simulated`` naming the
#: command, never a syntax error.
NOT_SIMULATED: list[tuple[str, str]] = [
    ("PASSWORD=SECRET", "PASSWORD"), ("CHECKSUM", "CHECKSUM"),
]


@pytest.mark.parametrize(("text", "open_", "built"), SIMULATED)
def test_tsrm_spelling_parses_to_its_statement(text, open_, built):
    for written in (text, text.lower()):
        stmts = parse_line(written, open_=open_)
        names = [type(s).__name__ for s in stmts[0]]
        assert built in names, (written, names)


@pytest.mark.parametrize(("text", "name"), NOT_SIMULATED)
def test_tsrm_spelling_not_simulated_is_named_not_a_syntax_error(text, name):
    with pytest.raises(ParseError) as e:  # the parser's answer, not_simulated in its details
        parse_line(text, open_=False)
    assert e.value.details["not_simulated"] == name
