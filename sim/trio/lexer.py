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
    |(?P<comment>'.*)
    |(?P<number>\$[0-9A-Fa-f]+|(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)
    |(?P<string>"[^"]*")
    |(?P<name>[A-Za-z_][A-Za-z0-9_]*)
    |(?P<op><>|<=|>=|[-+*/^=<>(),;:?#\[\]])
    """,
    re.X,
)


class Token(NamedTuple):
    """``kind`` is ``number``, ``string``, ``name`` (upper-cased) or ``op``; ``col`` 1-based."""

    kind: str
    text: str
    col: int


def tokenize(line: str, line_no: int) -> list[Token]:
    """The tokens of one source line (comments dropped)."""
    out: list[Token] = []
    pos, n = 0, len(line)
    while pos < n:
        m = _TOKEN.match(line, pos)
        if m is None:
            ch = line[pos]
            msg = "unterminated string" if ch == '"' else f"unexpected character {ch!r}"
            raise ParseError(msg, line=line_no, column=pos + 1, text=line)
        kind = m.lastgroup
        text = m.group()
        if kind == "name":
            text = text.upper()
            if text == "REM":
                break
        if kind not in ("ws", "comment"):
            out.append(Token(kind, text, pos + 1))  # type: ignore[arg-type]
        pos = m.end()
    return out


__all__ = ["Token", "tokenize"]
