"""The parser's fast paths against the rules they skip (issue 32, compile speed).

A statement starting with a name no rule claims goes straight to an assignment, and a name in
an expression that no rule claims straight to a variable or array element; which names the rules
claim is :func:`motionsim.sim.trio.language.parser.special_words`. With it answering "every
name" the parser runs every rule for every name: both ways must give the same statements and
the same errors, for every word the language knows, on every model, in statement and value
positions.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from motionsim.sim.errors import NotSimulated, ParseError
from motionsim.sim.trio.language import parser
from motionsim.sim.trio.language.parser import BASE, MC4, RESERVED, parse_line, special_words

FORMS = ("{w} = 1", "{w}(1) = 2", "{w}", "{w} 1, 2", "{w}(1, 2)", "{w}.3 = 1", "{w}: x = 1",
         "x = {w}", "x = {w}(1)", "x = {w}(1, 2) + 1", "x = {w}.2", "x = -{w} * 2",
         "PRINT {w}; {w}(0)", "IF {w} THEN {w} = 1 ELSE y = {w}", "FOR {w} = 1 TO {w}")


def _words() -> list[str]:
    words: set[str] = set()
    for dialect in (BASE, MC4):
        statement, value = special_words(dialect)
        words |= statement | value
    words |= RESERVED
    text = (Path(__file__).resolve().parents[3] / "docs" / "trio.md").read_text(encoding="utf-8")
    words |= {w.upper() for w in re.findall(r"[A-Za-z_][A-Za-z0-9_]*", text)[:3000]}
    words |= {"X", "COUNT", "MACHINE_SPEED_LIMIT_X", "IN_0_1", "A1", "_"}
    return sorted(words)


class _Every:
    """A set holding every name: no fast path taken."""

    def __contains__(self, word: object) -> bool:
        return True


def _outcome(text: str, dialect) -> object:
    try:
        return repr(parse_line(text, 3, dialect=dialect))
    except (ParseError, NotSimulated) as err:
        return (type(err).__name__, err.message, err.details.get("column"))


@pytest.mark.parametrize("dialect", [BASE, MC4], ids=lambda d: d.name)
def test_the_fast_paths_give_what_every_rule_gives(dialect, monkeypatch):
    lines = [form.format(w=w) for w in _words() for form in FORMS]
    fast = [_outcome(line, dialect) for line in lines]
    monkeypatch.setattr(parser, "special_words", lambda d: (_Every(), _Every()))
    slow = [_outcome(line, dialect) for line in lines]
    differ = [(line, f, s) for line, f, s in zip(lines, fast, slow, strict=True) if f != s]
    assert differ == []
    assert len(lines) > 5000
