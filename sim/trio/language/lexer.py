"""Trio BASIC tokens: one regular expression over a source line.

Keywords are case-insensitive (names are upper-cased); ``'`` and ``REM`` start a comment that
runs to the end of the line; numbers are decimal (``1.5``, ``.5``, ``2e3``) or ``$`` hex
(``$FF``). A character no token matches is a :class:`motionsim.sim.errors.ParseError` at its column.
"""

from __future__ import annotations

import re
from typing import NamedTuple

from ...errors import ParseError

#: One token after optional blanks; the group that matched is its kind (:data:`_KINDS`).
_TOKEN = re.compile(
    r"""[ \t\r]*(?:
     ([A-Za-z_][A-Za-z0-9_]*)
    |(<<|>>|<>|<=|>=|[-+*/^=<>(),;:?#\[\]])
    |(\$[0-9A-Fa-f]+|(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)
    |("[^"]*")
    |('.*)
    |([^ \t\r]))
    """,
    re.X,
)
_KINDS = (None, "name", "op", "number", "string", "comment", "bad")


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
        k = m.lastindex
        if k == 1:
            text = m.group(1).upper()
            if text == "REM":
                break
            append(_new(Token, ("name", text, m.start(1) + 1)))  # Token(...) without __new__
        elif k == 5:
            break  # a comment runs to the end of the line
        elif k == 6:
            text = m.group(6)
            msg = "unterminated string" if text == '"' else f"unexpected character {text!r}"
            raise ParseError(msg, line=line_no, column=m.start(6) + 1, text=line)
        elif k is not None:
            append(_new(Token, (_KINDS[k], m.group(k), m.start(k) + 1)))
    return out


__all__ = ["Token", "tokenize"]
