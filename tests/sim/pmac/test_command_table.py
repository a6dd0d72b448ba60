"""The PMAC on-line commands are one table (issue 31 item 4): every statement the parser
builds for an on-line command has exactly one row of ``host/commands.py``, and every row is
reached by a command the manuals write. The keyword table refers to its builders directly."""

from __future__ import annotations

import inspect

import pytest
from motionsim.sim.pmac.host import commands
from motionsim.sim.pmac.language import keywords
from motionsim.sim.pmac.language.parser import parse_line

#: One on-line command per row (TSRM on-line command pages; the forms the tests of each
#: family use).
ONLINE = [
    "&1", "&1E", "#1", "##0", "#1J+", "#1HM", "#1K", "#1O10", "#1$", "HOME1,2", "#1->X",
    "DEFINE ROT 100", "DELETE ROT", "DEFINE GATHER", "DELETE GATHER", "GATHER", "ENDGATHER",
    "DEFINE LOOKAHEAD 50,10",
    "DELETE LOOKAHEAD", "OPEN ROT", "OPEN PROG 1", "CLOSE", "B1", "R", "S", "Q", "MFLUSH", "H",
    "A", "/", "\\", "?", "%50", "I10", "I10..11=*", "P1=2", "P1..3=0", "P(P1+1)", "SAVE",
    "$$$", "LIST PLC 1",
    "M1->Y:$78802,8", "PC", "RX:$0", "WX:$0,1", "MS0,I910", "CLEAR ALL PLCS", "OPEN PLC 1",
    "ENABLE PLC 1", "DELETE PLCC 1", "CLEAR", "DELETE TRACE", "DEFINE UBUFFER 100",
    "DELETE ALL", "OPEN FORWARD", "PMATCH", "UNDEFINE", "M1->", "DEFINE COMP 4,1000",
    "DELETE COMP",
]  # fmt: skip


def test_every_online_statement_has_one_row_and_every_row_is_used():
    built = {type(s) for text in ONLINE for s, _, _ in parse_line(text)}
    missing = sorted(t.__name__ for t in built if t not in commands.BY_KIND)
    unused = sorted(t.__name__ for t in commands.BY_KIND if t not in built)
    assert missing == [] and unused == []
    assert len(commands.BY_KIND) == len(commands.TABLE)


@pytest.mark.parametrize("row", [k for k in keywords.TABLE if k.simulated],
                         ids=lambda k: k.name)
def test_a_simulated_keyword_names_its_builder_function_itself(row):
    assert inspect.isfunction(row.builds)
    params = list(inspect.signature(row.builds).parameters)
    assert len(params) == 2  # (parser, token)


def test_a_handler_takes_the_call_and_the_statement():
    for row in commands.TABLE:
        assert len(inspect.signature(row.run).parameters) == 2, row.kind.__name__
