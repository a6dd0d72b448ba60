"""Trio BASIC tokens: one regular expression over a source line.

Keywords are case-insensitive (names are upper-cased); ``'`` and ``REM`` start a comment that
runs to the end of the line; numbers are decimal (``1.5``, ``.5``, ``2e3``) or ``$`` hex
(``$FF``). A character no token matches is a :class:`motionsim.sim.errors.ParseError` at its column.

The token grammar is :data:`_ALTERNATIVES`, written once. :func:`tokenize_reference` reads it
one match at a time, the kind from the group that matched; :func:`tokenize`, what the parser
calls, takes every ``(blanks, token)`` pair of a line in one ``findall`` and the kind from the
token's first character (a program's compile time is about a quarter tokenising, issue 32). The
two agree token for token and error for error (tests/sim/trio/test_lexer.py compares them over
every example program, the test programs and generated lines); a line :func:`tokenize` meets an
error on is handed to :func:`tokenize_reference`, which words it.
"""

from __future__ import annotations

import re

from ...errors import ParseError

#: The tokens, first match wins: a name, an operator, a number, a string, a comment, any other
#: character (an error).
_ALTERNATIVES = (
    r"[A-Za-z_][A-Za-z0-9_]*",
    r"<<|>>|<>|<=|>=|[-+*/^=<>(),;:?#\[\]]",
    r"\$[0-9A-Fa-f]+|(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?",
    r'"[^"]*"',
    r"'.*",
    r"[^ \t\r]",
)
#: One token after optional blanks; the group that matched is its kind (:data:`_KINDS`).
_TOKEN = re.compile(r"[ \t\r]*(?:" + "|".join(f"({a})" for a in _ALTERNATIVES) + ")")
_KINDS = ("", "name", "op", "number", "string", "comment", "bad")
#: ``(blanks, token)``: the same grammar, no group per kind.
_PAIRS = re.compile(r"([ \t\r]*)(" + "|".join(_ALTERNATIVES) + ")")
#: A token's kind by its first character; a character missing here starts no token but the
#: error one; ``.``, ``$`` and ``"`` alone are errors too (no number / string follows).
_FIRST: dict[str, str] = {
    **dict.fromkeys("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz_", "name"),
    **dict.fromkeys("-+*/^=<>(),;:?#[]", "op"),
    **dict.fromkeys("0123456789.$", "number"),
    '"': "string",
    "'": "comment",
}


#: A token: ``(kind, text, col)`` — ``kind`` is ``number``, ``string``, ``name`` (``text``
#: upper-cased) or ``op``; ``col`` 1-based. A plain tuple, as the PMAC parser's tokens are: a
#: NamedTuple costs three times as much to build and twice as much to read, and a 1 000-line
#: program has ten thousand tokens (issue 32's compile time).
Token = tuple[str, str, int]


def tokenize(line: str, line_no: int) -> list[Token]:
    """The tokens of one source line (comments dropped)."""
    out: list[Token] = []
    append = out.append
    kind_of = _FIRST.get
    pos = 1
    for blanks, text in _PAIRS.findall(line):
        col = pos + len(blanks)
        pos = col + len(text)
        kind = kind_of(text[0])
        if kind == "name":
            text = text.upper()
            if text == "REM":
                break
        elif kind == "comment":
            break
        elif kind is None or (len(text) == 1 and (text == "." or text == "$" or text == '"')):
            return tokenize_reference(line, line_no)  # it raises the error, worded
        append((kind, text, col))
    return out


def tokenize_reference(line: str, line_no: int) -> list[Token]:
    """The tokens of one source line, one match at a time (what :func:`tokenize` agrees with)."""
    out: list[Token] = []
    append = out.append
    for m in _TOKEN.finditer(line):
        k = m.lastindex
        if k == 1:
            text = m.group(1).upper()
            if text == "REM":
                break
            append(("name", text, m.start(1) + 1))
        elif k == 5:
            break  # a comment runs to the end of the line
        elif k == 6:
            text = m.group(6)
            msg = "unterminated string" if text == '"' else f"unexpected character {text!r}"
            raise ParseError(msg, line=line_no, column=m.start(6) + 1, text=line)
        elif k is not None:
            append((_KINDS[k], m.group(k), m.start(k) + 1))
    return out


__all__ = ["Token", "tokenize", "tokenize_reference"]
