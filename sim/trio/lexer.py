"""Trio BASIC tokens: one regular expression over a source line.

Keywords are case-insensitive (names are upper-cased); ``'`` and ``REM`` start a comment that
runs to the end of the line; numbers are decimal (``1.5``, ``.5``, ``2e3``) or ``$`` hex
(``$FF``). A character no token matches is a :class:`motionsim.sim.errors.ParseError` at its column.
"""

from __future__ import annotations

import re
from typing import NamedTuple

from motionsim.sim.errors import ParseError

_TOKEN = re.compile(
    r"""
     (?P<ws>[ \t\r]+)
    |(?P<name>[A-Za-z_][A-Za-z0-9_]*)
    |(?P<op><>|<=|>=|[-+*/^=<>(),;:?#\[\]])
    |(?P<number>\$[0-9A-Fa-f]+|(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)
    |(?P<string>"[^"]*")
    |(?P<comment>'.*)
    |(?P<bad>.)
    """,
    re.X,
)


class Token(NamedTuple):
    """``kind`` is ``number``, ``string``, ``name`` (upper-cased) or ``op``; ``col`` 1-based."""

    kind: str
    text: str
    col: int


_new = tuple.__new__


def tokenize(line: str, line_no: int) -> list[Token]:
    """The tokens of one source line (comments dropped)."""
    out: list[Token] = []
    append = out.append
    for m in _TOKEN.finditer(line):
        kind = m.lastgroup
        if kind == "ws":
            continue
        if kind == "comment":
            break
        text = m.group()
        if kind == "name":
            text = text.upper()
            if text == "REM":
                break
        elif kind == "bad":
            msg = "unterminated string" if text == '"' else f"unexpected character {text!r}"
            raise ParseError(msg, line=line_no, column=m.start() + 1, text=line)
        append(_new(Token, (kind, text, m.start() + 1)))  # Token(...) without its __new__
    return out


__all__ = ["Token", "tokenize"]
