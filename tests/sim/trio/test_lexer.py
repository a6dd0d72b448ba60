"""The Trio BASIC tokens of one line (TJ1P-26/27: names upper-cased, ``'`` and REM comments, ``$``
hex numbers): blanks anywhere — trailing tabs and CR included — are no token, and a character
no token starts is an error at its column."""

from __future__ import annotations

import pytest
from motionsim.sim.errors import ParseError
from motionsim.sim.trio.language.lexer import tokenize


@pytest.mark.parametrize(("line", "tokens"), [
    ("x = 1  \t", [("name", "X", 1), ("op", "=", 3), ("number", "1", 5)]),
    ("\t VR(5).2=$FF\r", [("name", "VR", 3), ("op", "(", 5), ("number", "5", 6),
                          ("op", ")", 7), ("number", ".2", 8), ("op", "=", 10),
                          ("number", "$FF", 11)]),
    ('PRINT "a b"  \' a comment', [("name", "PRINT", 1), ("string", '"a b"', 7)]),
    ("a<>b REM the rest", [("name", "A", 1), ("op", "<>", 2), ("name", "B", 4)]),
    ("   ", []),
])
def test_tj1p_26_tokens_of_a_line(line, tokens):
    assert [tuple(t) for t in tokenize(line, 1)] == tokens


@pytest.mark.parametrize(("line", "column", "message"), [
    ('x = "ab', 5, "unterminated string"),
    ("x = 1 @", 7, "unexpected character '@'"),
])
def test_tj1p_26_a_character_no_token_starts_is_an_error_at_its_column(line, column, message):
    with pytest.raises(ParseError) as err:
        tokenize(line, 4)
    assert (err.value.details["line"], err.value.details["column"]) == (4, column)
    assert message in err.value.message
