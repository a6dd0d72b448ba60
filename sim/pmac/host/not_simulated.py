"""Valid Turbo PMAC commands that motionsim does not simulate.

When a command line fails to parse, the terminal asks :func:`which` whether the text at the
failing column, or at the start of the failing statement, is the start of one of these. The
wire answer stays the card's ``ERR003`` (the host must get an answer it can handle), but the
REST terminal reports ``not_simulated`` naming the command, so a user does not mistake it for
a typo. ``docs/pmac.md`` lists what is
simulated. Command names from the Turbo SRM on-line command list (TSRM p260–p420) ``[BK]``
for the spelling of a few abbreviations.

The commands come from the keyword table (:mod:`motionsim.sim.pmac.language.keywords`): a row
or an object marked not simulated is answered here; a row becomes simulated by giving it a
builder. A pattern never shadows a command the parser accepts: it is consulted only after a
parse error.
"""

from __future__ import annotations

import re
from typing import Final

from ..language import keywords

#: Valid commands the keyword table cannot hold as words (the lexer would split them into
#: letters that start other commands: ``MS``, ``LIST PE``); (pattern, what to call it).
_LETTER_COMMANDS: Final[tuple[tuple[str, str], ...]] = (
    (r"LIST\s*(PE|PC)\b", "LIST PE / LIST PC"),
    (r"CLEAR\s*ALL(?!\s*PLCS)", "CLEAR ALL"),
    (r"BLKSTART", "BLKSTART"),
)
#: (pattern at the failing column, what to call it): the keyword table's not-simulated
#: rows and objects (:func:`motionsim.sim.pmac.language.keywords.not_simulated`), then the
#: letter commands.
_COMMANDS: Final[tuple[tuple[str, str], ...]] = (
    *keywords.not_simulated(), *_LETTER_COMMANDS,
)
_ADDRESSING: Final = re.compile(r"(?:\s*[&#]\s*\d+)*\s*")
_COMPILED: Final = tuple((re.compile(p, re.IGNORECASE), name) for p, name in _COMMANDS)


def word_start(text: str, column: int) -> int:
    """0-based start of the word holding 1-based ``column``: the parser reads unknown words
    letter by letter, so a failing column can be inside one (``SAVE`` fails at ``V``)."""
    start = min(max(0, column - 1), len(text))
    while start > 0 and (text[start - 1].isalpha() or text[start - 1] == "$"):
        start -= 1
    return start


def command_start(text: str, column: int) -> int:
    """0-based start of the blank-delimited command holding 1-based ``column`` (``2+3``
    fails as a whole; ``I10 nonsense`` fails at ``nonsense``)."""
    start = min(max(0, column - 1), len(text))
    while start > 0 and not text[start - 1].isspace():
        start -= 1
    return start


def which(text: str, column: int, statement_start: int | None = None) -> str | None:
    """The not-simulated command starting at the word holding 1-based ``column`` or, failing
    that, at the failing statement's 0-based ``statement_start`` past any ``&n`` / ``#n``
    addressing (``LIST LOOKAHEAD`` fails at ``LOOKAHEAD``, a valid command all the same), or
    None."""
    starts = [word_start(text, column)]
    if statement_start is not None:
        starts.append(_ADDRESSING.match(text, max(0, statement_start)).end())  # type: ignore[union-attr]
    for start in starts:
        rest = text[start:].lstrip()
        for pattern, name in _COMPILED:
            if pattern.match(rest):
                return name
    return None


def message(name: str) -> str:
    """What the REST terminal says for a not-simulated command."""
    return (
        f"{name} is a valid Turbo PMAC command that motionsim does not simulate "
        "(docs/pmac.md lists what is simulated)"
    )


__all__ = ["command_start", "message", "which", "word_start"]
