"""PLC statements of real programs that the on-line parser has no word for (spec §12.2).

One table, :data:`IDIOMS`: the keyword's pattern (with the abbreviations and port letters the
card accepts) and the builder of its statement from the text that follows it.

* ``ADDRESS#{n}`` / ``ADDRESS&{n}`` (``ADR``): the program's own modal motor / coordinate
  system, for the ``CMD`` statements that follow and, in a PLC, for its ``Q`` variables
  (default #1, &1) ``[BK]`` (spec §12.2; the Turbo page was not retrieved).
* ``COMMAND"{text}"`` = ``CMD"{text}"``, with a reply-port letter ``S`` ``P`` ``R`` ``A``
  (``CMDS``...; TSRM p421): ``{text}`` goes to the background command interpreter; its reply
  goes nowhere in the simulator ``[INF]``. ``CMD^{letter}`` issues the control character
  ``<CTRL-letter>`` (TSRM p424: ``CMD^D`` disables all PLCs).
* ``SEND"{text}"`` with the same port letters (``SENDS``, ``SENDP``...) ``[BK]``: an
  unsolicited line to a host port.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from ...errors import ParseError


@dataclass(frozen=True, slots=True)
class Address:
    """``ADDRESS#{n}`` (``kind`` ``#``) or ``ADDRESS&{n}`` (``&``); ``by_p``: ``ADDRESS#P{n}``
    / ``ADDRESS&P{n}``, the motor / CS number is the value of P-variable ``n`` when the
    statement runs (Turbo PMAC "P-variable addressing" ``[BK]``)."""

    kind: str
    n: int
    by_p: bool = False


@dataclass(frozen=True, slots=True)
class Command:
    """``CMD"{text}"`` (``control`` False) or ``CMD^{letter}`` (``text`` is the control
    character itself); ``port`` is the reply-port letter ("" for none)."""

    text: str
    port: str = ""
    control: bool = False


@dataclass(frozen=True, slots=True)
class SendText:
    """``SEND{port}"{text}"``."""

    text: str
    port: str = ""


_ARG_ADDRESS = re.compile(r"\s*([#&])\s*(P?)\s*(\d+)", re.IGNORECASE)
_ARG_STRING = re.compile(r'\s*"([^"]*)"')
_ARG_CONTROL = re.compile(r"\s*\^\s*([A-Za-z])")

Builder = Callable[[str, str, int], tuple[object, int]]


def _error(message: str, column: int, text: str) -> ParseError:
    return ParseError(message, column=column, text=text, pmac_error="ERR003")


def _address(word: str, text: str, pos: int) -> tuple[object, int]:
    m = _ARG_ADDRESS.match(text, pos)
    if m is None:
        raise _error("ADDRESS needs #{motor} or &{coordinate system}", pos + 1, text)
    n = int(m.group(3))
    if m.group(2):
        if not 0 <= n <= 8191:
            raise _error(f"ADDRESS{m.group(1)}P{n}: no P{n} (0..8191)", m.start(3) + 1, text)
        return Address(m.group(1), n, by_p=True), m.end()
    limit = 32 if m.group(1) == "#" else 16
    if not 1 <= n <= limit:
        raise _error(f"ADDRESS{m.group(1)}{n}: out of 1..{limit}", m.start(3) + 1, text)
    return Address(m.group(1), n), m.end()


def _port_letter(word: str) -> str:
    stem = "SEND" if word.startswith("SEND") else ("COMMAND" if word.startswith("COMMAND")
                                                   else "CMD")
    return word[len(stem):]


def _command(word: str, text: str, pos: int) -> tuple[object, int]:
    port = _port_letter(word)
    m = _ARG_STRING.match(text, pos)
    if m is not None:
        return Command(m.group(1), port), m.end()
    m = _ARG_CONTROL.match(text, pos)
    if m is not None:
        return Command(chr(ord(m.group(1).upper()) - 64), port, control=True), m.end()
    raise _error(f'{word} needs "text" or ^letter', pos + 1, text)


def _send(word: str, text: str, pos: int) -> tuple[object, int]:
    m = _ARG_STRING.match(text, pos)
    if m is None:
        raise _error(f'{word} needs "text"', pos + 1, text)
    return SendText(m.group(1), _port_letter(word)), m.end()


#: keyword pattern -> builder ``(KEYWORD, line, position after it) -> (statement, end)``.
IDIOMS: tuple[tuple[str, Builder], ...] = (
    (r"ADDRESS|ADR", _address),
    (r"COMMAND[SPRA]?|CMD[SPRA]?", _command),
    (r"SEND[SPRA]?", _send),
)

PATTERN = "|".join(p for p, _ in IDIOMS)
_MATCHERS = [(re.compile(rf"(?:{p})\Z", re.IGNORECASE), b) for p, b in IDIOMS]


def build(word: str, text: str, pos: int) -> tuple[object, int]:
    """The statement of idiom keyword ``word`` (as matched by :data:`PATTERN`) whose argument
    starts at ``pos`` of ``text``; returns it with the position after it.

    Raises:
        ParseError: the argument is missing or out of range (column, ERR003).
    """
    up = word.upper()
    for pat, builder in _MATCHERS:
        if pat.match(up):
            return builder(up, text, pos)
    raise _error(f"unknown PLC keyword {word!r}", pos + 1, text)  # pragma: no cover


def message_word(p: Any, tok: tuple[str, str, int, int]) -> Any:
    """Keyword-table builder for a motion-program line: ``CMD``/``SEND`` with any port letter
    become a stored message (a ``SEND`` reaches the host when the line is calculated; a
    ``CMD`` takes no action in a motion program ``[INF]``); ``CMD^{letter}`` stores the
    control character."""
    from . import statements as st  # statements imports this module

    word = tok[1]
    stmt, end = build(word, p.text, tok[3])
    p.skip_to(end)
    kind = "SEND" if word.startswith("SEND") else "CMD"
    return st.Message(kind, stmt.text, stmt.port)  # type: ignore[attr-defined]


def address_word(p: Any, tok: tuple[str, str, int, int]) -> Any:
    """Keyword-table builder: ``ADDRESS#n`` / ``ADDRESS&n`` in a motion program."""
    stmt, end = build(tok[1], p.text, tok[3])
    p.skip_to(end)
    return stmt


__all__ = [
    "IDIOMS", "PATTERN", "Address", "Command", "SendText", "address_word", "build",
    "message_word",
]  # fmt: skip
