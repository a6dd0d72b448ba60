"""Text -> statements for Turbo PMAC PLC programs (TUM p253, p376; TSRM p381, p423-424).

A PLC line holds one or more of:

* assignments ``P1=P1+1``, ``M1=1`` (M-variables are the PLC's I/O), ``I5=3``, ``Q2=P1*3``;
* ``IF (condition)``, ``ELSE``, ``ENDIF`` (``ENDI``), ``WHILE (condition)``, ``ENDWHILE``
  (``ENDW``). An ``IF (...)`` or ``WHILE (...)`` followed by statements on the same line is a
  one-line block that ends with the line ``[INF]``;
* ``CMD"..."`` (an on-line command for the background command interpreter) and
  ``SEND"..."`` (a message to the host port);
* ``ENABLE PLC n`` / ``DISABLE PLC n`` (lists and ranges as on-line);
* while entering: ``CLEAR`` and ``CLOSE`` (handled by
  :class:`motionsim.sim.pmac.tasks.plc.PlcTable`).

Conditions: ``expression comparator expression`` with the comparators ``=`` ``!=`` ``>``
``!>`` ``<`` ``!<`` ``~`` ``!~`` (TUM p253, TSRM p23), combined with ``AND`` / ``OR`` inside
the parentheses, and
parenthesised sub-conditions. ``AND`` binds tighter than ``OR`` ``[INF]``. In PLCs a
condition may go on over the following lines, each starting ``AND (...)`` or ``OR (...)``
(TUM p253: multi-line conditions are for PLCs only); they extend the ``IF``/``WHILE`` just
above them with the same precedence. An ``AND``/``OR`` line anywhere else is ERR003.
Synchronous assignments (``M1==1``) and motion statements belong to motion programs and are
refused in PLCs (ERR003).

Errors are :class:`motionsim.sim.errors.ParseError` with the 1-based ``column`` and ``pmac_error``
``"ERR003"``; nothing is stored from a line that fails.
"""

from __future__ import annotations

import operator
import re
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from motionsim.sim.errors import ParseError
from motionsim.sim.pmac.language import plc_idioms
from motionsim.sim.pmac.language import plc_statements as plc_st
from motionsim.sim.pmac.language import statements as st
from motionsim.sim.pmac.language.expressions import MAX_NESTING, Expr, too_deep
from motionsim.sim.pmac.language.parser import parse_expression, parse_line

_ERR = "ERR003"

Cond = Callable[[Any, int], bool]

_KEYWORDS = (
    r"END\s*WHILE", r"ENDW", r"END\s*IF", r"ENDI", "WHILE", "ELSE", "IF", "CLEAR", "CLOSE",
    "OPEN", "AND", "OR", plc_idioms.PATTERN,
)  # fmt: skip
#: ENABLE / DISABLE (``ENA``, ``DIS``) are keywords before ``PLC`` (``ENAPLC6``, ``DIS PLC 2``).
_KW = re.compile(
    r'"[^"]*"|(?<![A-Za-z0-9_])(?:(?P<kw>' + "|".join(_KEYWORDS) + r")(?![A-Za-z])"
    r"|(?P<en>ENABLE|ENA|DISABLE|DIS)(?=\s*PLC))",
    re.IGNORECASE,
)
_IDIOM = re.compile(rf"(?:{plc_idioms.PATTERN})\Z", re.IGNORECASE)
_CMP = re.compile(r"!=|!>|!<|!~|<>|>=|<=|=|>|<|~")
_COMPARATORS: dict[str, Callable[[float, float], bool]] = {
    "=": operator.eq,
    "!=": operator.ne,
    ">": operator.gt,
    "!>": operator.le,
    "<": operator.lt,
    "!<": operator.ge,
    # ``~`` approximately equal, within one; ``!~`` its negation (TSRM p23 lists both; the
    # meaning is [BK], spec §12.1)
    "~": lambda a, b: abs(a - b) <= 1.0,
    "!~": lambda a, b: abs(a - b) > 1.0,
}
_ABBREV = {"ENDW": "ENDWHILE", "ENDI": "ENDIF", "ENA": "ENABLE", "DIS": "DISABLE"}


# -- statements of a PLC program ------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class If:
    """``IF (condition)``; ``inline`` when statements follow on the same line."""

    cond: Cond
    text: str
    inline: bool = False


@dataclass(frozen=True, slots=True)
class Else:
    """``ELSE``."""


@dataclass(frozen=True, slots=True)
class EndIf:
    """``ENDIF``."""


@dataclass(frozen=True, slots=True)
class While:
    """``WHILE (condition)``; ``inline`` when statements follow on the same line."""

    cond: Cond
    text: str
    inline: bool = False


@dataclass(frozen=True, slots=True)
class EndWhile:
    """``ENDWHILE``: the scan ends here; the next scan starts at the WHILE (seed 003)."""


@dataclass(frozen=True, slots=True)
class Set:
    """An immediate assignment ``P1=expr``."""

    kind: str
    index: Expr
    value: Expr


@dataclass(frozen=True, slots=True)
class Cmd:
    """``CMD"text"``: queued to the background command interpreter."""

    text: str


@dataclass(frozen=True, slots=True)
class Send:
    """``SEND{port}"text"``: a message to the host."""

    text: str
    port: str = ""


@dataclass(frozen=True, slots=True)
class CondLine:
    """A continuation line ``AND (condition)`` / ``OR (condition)`` of the IF/WHILE above."""

    op: str
    cond: Cond
    text: str


PlcStatement = CondLine | If | Else | EndIf | While | EndWhile | Set | Cmd | Send | plc_st.EnablePlc


# -- conditions -----------------------------------------------------------------------------


def _error(message: str, column: int, text: str) -> ParseError:
    return ParseError(message, column=column, text=text, pmac_error=_ERR)


def _shift(e: ParseError, offset: int, text: str) -> ParseError:
    return ParseError(
        e.message, column=(e.column or 1) + offset, text=text, pmac_error=e.pmac_error or _ERR
    )


def _top_level_split(s: str, word: str) -> list[tuple[int, str]]:
    """Split ``s`` at ``word`` (AND / OR) outside parentheses; ``(offset, part)`` pairs."""
    parts: list[tuple[int, str]] = []
    depth, start = 0, 0
    pat = re.compile(r"(?<![A-Za-z0-9_])" + word + r"(?![A-Za-z])", re.IGNORECASE)
    i = 0
    while i < len(s):
        ch = s[i]
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
        elif depth == 0 and pat.match(s, i):
            parts.append((start, s[start:i]))
            i += len(word)
            start = i
            continue
        i += 1
    parts.append((start, s[start:]))
    return parts


def _comparator_at_top(s: str) -> re.Match[str] | None:
    depth = 0
    for i, ch in enumerate(s):
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
        elif depth == 0 and ch in "=!<>~":
            return _CMP.match(s, i)
    return None


def parse_condition(s: str, offset: int, line: str) -> Cond:
    """A condition (the text inside ``IF (...)``); ``offset`` = its column - 1 in ``line``."""
    ors = _top_level_split(s, "OR")
    if len(ors) > 1:
        subs = [parse_condition(p, offset + o, line) for o, p in ors]
        return lambda v, c: any(f(v, c) for f in subs)
    ands = _top_level_split(s, "AND")
    if len(ands) > 1:
        subs = [parse_condition(p, offset + o, line) for o, p in ands]
        return lambda v, c: all(f(v, c) for f in subs)
    stripped = s.strip()
    lead = len(s) - len(s.lstrip())
    if not stripped:
        raise _error("expected a condition", offset + lead + 1, line)
    m = _comparator_at_top(s)
    if m is None:
        if stripped.startswith("(") and stripped.endswith(")"):
            if _comparator_at_top(stripped[1:-1]) is not None:
                # TUM p252: parentheses around the simple conditions of a condition are illegal
                # (IF((P1>-20) AND (P1<20)) is an error); inside expressions they are fine
                raise _error("no parentheses around a simple condition: write "
                             "(P1>-20 AND P1<20), not ((P1>-20) AND (P1<20))",
                             offset + lead + 1, line)
            return parse_condition(stripped[1:-1], offset + lead + 1, line)
        raise _error("expected a comparison (= != > !> < !< ~ !~)", offset + lead + 1, line)
    op = m.group(0)
    if op not in _COMPARATORS:
        raise _error(f"comparator {op!r} is not PMAC syntax", offset + m.start() + 1, line)
    try:
        left = parse_expression(s[: m.start()])
    except ParseError as e:
        raise _shift(e, offset, line) from None
    try:
        right = parse_expression(s[m.end() :])
    except ParseError as e:
        raise _shift(e, offset + m.end(), line) from None
    f = _COMPARATORS[op]
    return lambda v, c: f(left(v, c), right(v, c))


# -- lines ----------------------------------------------------------------------------------


def _next_keyword(text: str, pos: int) -> re.Match[str] | None:
    for m in _KW.finditer(text, pos):
        if m.group("kw") is not None or m.group("en") is not None:
            return m
    return None


def _matching_paren(text: str, open_at: int) -> int:
    depth = 0
    for i in range(open_at, len(text)):
        if text[i] == "(":
            depth += 1
        elif text[i] == ")":
            depth -= 1
            if depth == 0:
                return i
    raise _error("missing )", open_at + 1, text)


def _segment(text: str, start: int, end: int) -> list[Any]:
    """Assignments, CMD and SEND between two keywords."""
    seg = text[start:end]
    try:
        stmts = parse_line(seg, open_=True)
    except ParseError as e:
        raise _shift(e, start, text) from None
    out: list[Any] = []
    for stmt, s0, _ in stmts:
        col = start + s0 + 1
        if isinstance(stmt, st.Assign):
            if stmt.synchronous:
                raise _error("synchronous assignment is for motion programs", col, text)
            out.append(Set(stmt.target.kind, stmt.target.index, stmt.value))
        elif getattr(stmt, "run_online", None) is not None and getattr(stmt, "in_program", True):
            out.append(stmt)  # a family that runs itself (MSR / MSW...)
        elif isinstance(stmt, st.Message):
            out.append(Cmd(stmt.text) if stmt.kind == "CMD" else Send(stmt.text, stmt.port))
        else:
            raise _error(f"{type(stmt).__name__} is not a PLC statement", col, text)
    return out


def _code(text: str) -> str:
    """The line without its ``;`` comment (a ``;`` inside a quoted string is text)."""
    quoted = False
    for i, ch in enumerate(text):
        if ch == '"':
            quoted = not quoted
        elif ch == ";" and not quoted:
            return text[:i]
    return text


def parse_plc_line(text: str) -> list[tuple[Any, int]]:
    """The statements of one PLC line with their 1-based columns.

    ``CLEAR`` and ``CLOSE`` come back as :class:`motionsim.sim.pmac.language.plc_statements.Clear`
    and
    :class:`motionsim.sim.pmac.language.statements.Close`.

    Raises:
        ParseError: column, ERR003.
    """
    deep = too_deep(text)  # conditions parse recursively: bound the nesting first
    if deep is not None:
        raise _error(f"expression nested deeper than {MAX_NESTING} levels (the limit)", deep,
                     text)
    out: list[tuple[Any, int]] = []
    text = _code(text)
    pos, n = 0, len(text)
    while pos < n:
        while pos < n and text[pos].isspace():
            pos += 1
        if pos >= n:
            break
        m = _KW.match(text, pos)
        if m is None or (m.group("kw") is None and m.group("en") is None):
            nxt = _next_keyword(text, pos)
            end = nxt.start() if nxt is not None else n
            out.extend((s, pos + 1) for s in _segment(text, pos, end))
            pos = end
            continue
        kw = re.sub(r"\s+", "", (m.group("kw") or m.group("en")).upper())
        kw = _ABBREV.get(kw, kw)
        col = pos + 1
        pos = m.end()
        if _IDIOM.match(kw):
            stmt, pos = plc_idioms.build(kw, text, pos)
            out.append((stmt, col))
        elif kw in ("IF", "WHILE"):
            while pos < n and text[pos].isspace():
                pos += 1
            if pos >= n or text[pos] != "(":
                raise _error(f"{kw} needs (condition)", pos + 1, text)
            close = _matching_paren(text, pos)
            cond = parse_condition(text[pos + 1 : close], pos + 1, text)
            cond_text = text[pos : close + 1]
            pos = close + 1
            inline = text[pos:].strip() != ""
            out.append(((If if kw == "IF" else While)(cond, cond_text, inline), col))
        elif kw == "ELSE":
            out.append((Else(), col))
        elif kw == "ENDIF":
            out.append((EndIf(), col))
        elif kw == "ENDWHILE":
            out.append((EndWhile(), col))
        elif kw == "CLEAR":
            out.append((plc_st.Clear(), col))
        elif kw == "CLOSE":
            out.append((st.Close(), col))
        elif kw in ("ENABLE", "DISABLE"):
            nxt = _next_keyword(text, pos)
            end = nxt.start() if nxt is not None else n
            seg = text[col - 1 : end]
            head = re.match(r"\s*[A-Z]+?\s*PLCC?\s*[\d\s,.]*", seg, re.IGNORECASE)
            stop = head.end() if head is not None else len(seg)
            try:
                stmts = parse_line(seg[:stop])
            except ParseError as e:
                raise _shift(e, col - 1, text) from None
            out.append((stmts[0][0], col))
            pos = col - 1 + stmts[0][2]
        elif kw == "OPEN":
            # OPEN while a buffer is open: "buffer already in use" (TSRM p381).
            raise ParseError(
                "a buffer is already open: CLOSE first", column=col, text=text, pmac_error="ERR007"
            )
        else:  # AND / OR: a continuation line of a multi-line condition
            if out:
                raise _error(f"{kw} must start its line", col, text)
            while pos < n and text[pos].isspace():
                pos += 1
            if pos >= n or text[pos] != "(":
                raise _error(f"{kw} needs (condition)", pos + 1, text)
            close = _matching_paren(text, pos)
            cond = parse_condition(text[pos + 1 : close], pos + 1, text)
            out.append((CondLine(kw, cond, text[pos : close + 1]), col))
            pos = close + 1
    return out


__all__ = [
    "Cmd",
    "CondLine",
    "Else",
    "EndIf",
    "EndWhile",
    "If",
    "PlcStatement",
    "Send",
    "Set",
    "While",
    "parse_condition",
    "parse_plc_line",
]
