"""The keyword table (sim/pmac/language/keywords.py) drives the lexer, the parser's dispatch
and the not-simulated answer: every spelling of every command word is read whole and is
never a parse error (TSRM p23: blanks are not significant, so ``END IF`` is ``ENDIF``); an
invalid command names its column and what was expected there (spec pmac.md §12.1)."""

from __future__ import annotations

import pytest
from motionsim.sim.errors import ParseError
from motionsim.sim.pmac.language import keywords
from motionsim.sim.pmac.language.parser import parse_line, tokenize

#: A valid use of every simulated row, {spelling} standing for each of its spellings, and
#: whether it is written with a buffer open.
USES: dict[str, tuple[str, bool]] = {
    "DEFINE": ("&1 {} ROT 100", False), "DELETE": ("&1 {} ROT", False),
    "OPEN": ("{} PROG 3", False), "CLOSE": ("{}", False), "CLEAR": ("{}", True),
    "LIST": ("{} PLC 1", False), "MFLUSH": ("&1 {}", False), "SAVE": ("{}", False),
    "ENABLE": ("{} PLC 3", False), "DISABLE": ("{} PLC 3..5", False),
    "VERSION": ("{}", False), "CID": ("{}", False), "CPU": ("{}", False),
    "VID": ("{}", False), "TYPE": ("{}", False), "SIZE": ("{}", False), "PR": ("&1{}", False),
    "HOME": ("#1{}", False), "HOMEZ": ("#1{}", False), "LINEAR": ("{} X1", True),
    "RAPID": ("{} X1", True), "CIRCLE": ("{}1", True), "SPLINE": ("{}1", True),
    "PVT": ("{}100", True), "PSET": ("{} X0", True), "INC": ("{}(X,Y)", True),
    "ABS": ("{}", True), "TA": ("{}10", True), "TS": ("{}0", True), "TM": ("{}(P1)", True),
    "DWELL": ("{}0", True), "DELAY": ("{} 10", True), "SEND": ('{}"HI"', True),
    "COMMAND": ('{}"#1J+"', True), "ADDRESS": ("{}&2", True), "UNDEFINE": ("&1{}", False),
    "FRAX": ("{}(X,Y)", True), "IF": ("{} (P1 !< 2 AND M11 = 0)", True),
    "ELSE": ("{} X-10", True), "ENDIF": ("{}", True), "WHILE": ("{}(M11=0) WAIT", True),
    "ENDWHILE": ("{}", True), "GOTO": ("{}(P1*10)", True), "GOSUB": ("{}101 A1 B(P2)", True),
    "CALL": ("{}35.1 X5", True), "RETURN": ("{}", True), "READ": ("{}(A,B)", True),
    "STOP": ("{}", True), "WAIT": ("{}", True), "BLOCKSTART": ("{}", True),
    "BLOCKSTOP": ("{}", True), "PMATCH": ("&1 {}", False),
    # a PLC's continuation lines (PUM p162), rows since issue 31
    "AND": ("{} (P1=1)", True), "OR": ("{} (M11=0)", True),
    # data gathering (issue 34)
    "GATHER": ("{}", False), "ENDGATHER": ("{}", False),
}
CASES = [
    (k.name, spelling, *USES[k.name])
    for k in keywords.TABLE if k.simulated for spelling in k.spellings
]


def test_every_simulated_row_has_a_use_here():
    assert {k.name for k in keywords.TABLE if k.simulated} == set(USES)


@pytest.mark.parametrize(("name", "spelling", "use", "open_"), CASES)
def test_tsrm_p23_every_spelling_of_every_keyword_parses(name, spelling, use, open_):
    for written in (spelling, spelling.lower(), spelling.title()):
        stmts = parse_line(use.format(written), open_=open_)
        assert stmts, (name, written)


@pytest.mark.parametrize("spelling", [s for k in keywords.TABLE for s in k.spellings])
def test_every_spelling_is_one_token_and_finds_its_row(spelling):
    (kind, text, start, end), *_ = tokenize(spelling + " 1")
    assert kind == "word" and (start, end) == (0, len(spelling))
    assert keywords.lookup(text) is keywords.BY_SPELLING[spelling.replace(" ", "")]


def test_tsrm_p23_blanks_inside_end_if_and_end_while_are_not_significant():
    for text in ("END IF", "End  If", "ENDIF", "ENDI", "end\tif"):
        assert type(parse_line(text, open_=True)[0][0]).__name__ == "EndIf"
    for text in ("END WHILE", "EndWhile", "ENDW"):
        assert type(parse_line(text, open_=True)[0][0]).__name__ == "EndWhile"


@pytest.mark.parametrize(("text", "column", "expected"), [
    ("OPEN PRUG 1", 6, "OPEN what?"),
    ("IF P1=0", 4, "IF needs ({condition})"),
    ("IF (P1 >= 0)", 8, "comparator '>=' is not PMAC syntax"),
    ("GOSUB", 6, "GOSUB needs a label"),
    ("READ (A)", 6, "READ needs (letters)"),
    ("READ(A,N)", 8, "READ: expected a letter"),
    ("WHILE (P1=1", 7, "missing )"),
])
def test_an_invalid_command_names_the_column_and_what_was_expected(text, column, expected):
    with pytest.raises(ParseError) as e:
        parse_line(text, open_=True)
    assert e.value.details["column"] == column, e.value.message
    assert expected in e.value.message
    assert e.value.pmac_error == "ERR003"
