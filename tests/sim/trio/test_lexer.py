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


# -- tokenize (the parser's, one findall a line) against tokenize_reference -----------------


def _corpus_lines() -> list[str]:
    """Every line of the example programs, of the Trio test sources (their BASIC in strings,
    and Python besides: plenty of characters no token starts) and of both compile benches."""
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parents[3]
    sys.path.insert(0, str(root / "bench"))
    import bench_trio_include
    import bench_trio_library

    texts = [p.read_text(encoding="utf-8") for p in sorted((root / "examples").rglob("*"))
             if p.suffix.lower() in (".bas", ".bal")]
    texts += [p.read_text(encoding="utf-8") for p in sorted(Path(__file__).parent.glob("*.py"))]
    texts += [bench_trio_include.main_program(), bench_trio_library.main_program(),
              bench_trio_library.library()]
    return [line for text in texts for line in text.replace("\r\n", "\n").split("\n")]


def _generated_lines(n: int = 3000) -> list[str]:
    """Lines of random pieces: names in both cases, REM inside names, numbers with exponents,
    lone '.', '$' and '"', strings, comments, blanks, characters outside ASCII."""
    import random

    rnd = random.Random(32)
    pieces = ["x", "Rem", "rEm", "remark", "REM", "_a1", "VR", "(", ")", "<<", ">>", "<>", "<=",
              ">=", "=", "<", "-", "+", "*", "/", "^", ":", ",", ";", "?", "#", "[", "]", "1",
              "1.5", ".5", "2e3", "1E-2", "$ff", "$", ".", "..", '"', '"ab"', '""', "'", "' c",
              " ", "\t", "\r", "@", "!", "é", "٣", "$G", "1.", "3.x", "a.5", "}", "{", "%"]
    return ["".join(rnd.choice(pieces) for _ in range(rnd.randint(0, 12))) for _ in range(n)]


def _outcome(fn, line: str):
    try:
        return [tuple(t) for t in fn(line, 7)]
    except ParseError as err:
        return ("error", err.message, err.details["line"], err.details["column"])


def test_the_parsers_tokenize_agrees_with_the_reference_on_every_line():
    from motionsim.sim.trio.language.lexer import tokenize_reference

    lines = _corpus_lines() + _generated_lines()
    assert len(lines) > 5000
    differ = [line for line in lines
              if _outcome(tokenize, line) != _outcome(tokenize_reference, line)]
    assert differ == []
    assert any(isinstance(_outcome(tokenize, line), tuple) for line in lines)  # errors too
