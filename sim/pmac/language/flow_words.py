"""Builders of the control-flow words (rows of :mod:`.keywords`; statements in
:mod:`.flow_statements`), for motion programs and PLC programs alike. Conditions are read
from the line's tokens by the parser (``p.condition()``: one condition syntax for PLCs and
motion programs, TUM p252).
"""

from __future__ import annotations

from typing import Any

from . import flow_statements as fl
from .conditions import any_of_all

Token = tuple[str, str, int, int]

#: Conditions already parsed, by their text (a condition is a pure function of the variables;
#: real programs repeat theirs: ``If (A_Axis = 1)`` for every axis and point).
_CONDITIONS: dict[str, Any] = {}
_CACHE_SIZE = 4096

#: What makes ``{letter}{data}`` an assignment or a definition rather than an argument.
_ASSIGNING = frozenset(["=", "==", "&=", "|=", "^=", "->"])
#: Argument letters of GOSUB / CALL / READ (TSRM p466): any letter but N and O (labels).
_ARG_LETTERS = frozenset("ABCDEFGHIJKLMPQRSTUVWXYZ")


def _parenthesised(p: Any, word: str) -> tuple[Any, int]:
    """``({condition})`` at the parser's position: the condition and the index of the token
    after the closing parenthesis (the parser is moved there)."""
    tok = p.peek()
    if tok is None or tok[0] != "op" or tok[1] != "(":
        raise p.error(f"{word} needs ({{condition}})", tok)
    toks, depth, close = p.toks, 0, -1
    for k in range(p.i, len(toks)):
        t = toks[k]
        if t[0] == "op" and t[1] == "(":
            depth += 1
        elif t[0] == "op" and t[1] == ")":
            depth -= 1
            if depth == 0:
                close = k
                break
    if close < 0:
        raise p.error("missing ) after the condition", tok)
    inner = p.text[tok[2] + 1 : toks[close][2]]
    cond = _CONDITIONS.get(inner)
    if cond is None:  # (errors are raised here, with their columns in this line)
        p.i += 1
        cond = p.condition()
        if p.i != close:
            raise p.error("expected ) after the condition", p.peek())
        if len(_CONDITIONS) >= _CACHE_SIZE:
            _CONDITIONS.clear()
        _CONDITIONS[inner] = cond
    p.i = close + 1
    return cond, close


def _condition(p: Any, word: str) -> tuple[Any, str]:
    """``({condition})`` after IF / WHILE / AND / OR: the condition and its text; the parser
    is moved past the closing parenthesis. Further ``AND ({condition})`` / ``OR
    ({condition})`` on the same line join it (``IF (P1=1) AND (P2=1)``, as PLC programs write
    them), AND binding tighter than OR (TUM p252) ``[INF]`` for the one-line form."""
    first = p.peek()
    cond, close = _parenthesised(p, word)
    groups: list[list[Any]] = [[cond]]
    while p.at("word") and p.peek()[1] in ("AND", "OR") and p.at_op(1, "("):
        if p.take()[1] == "OR":
            groups.append([])
        more, close = _parenthesised(p, word)
        groups[-1].append(more)
    return any_of_all(groups), p.text[first[2] : p.toks[close][3]]


def _more(p: Any) -> bool:
    return p.peek() is not None


def if_(p: Any, tok: Token) -> fl.If:
    cond, text = _condition(p, "IF")
    return fl.If(cond, text, _more(p), tok[2] + 1)


def while_(p: Any, tok: Token) -> fl.While:
    cond, text = _condition(p, "WHILE")
    return fl.While(cond, text, _more(p), tok[2] + 1)


def else_(p: Any, tok: Token) -> fl.Else:
    return fl.Else(_more(p), tok[2] + 1)


def endif(p: Any, tok: Token) -> fl.EndIf:
    return fl.EndIf(tok[2] + 1)


def endwhile(p: Any, tok: Token) -> fl.EndWhile:
    return fl.EndWhile(tok[2] + 1)


def cond_line(p: Any, tok: Token) -> fl.CondLine:
    """``AND ({condition})`` / ``OR ({condition})`` starting a line (a PLC's multi-line
    condition); whether it may stand here is the PLC compiler's rule."""
    cond, text = _condition(p, tok[1])
    return fl.CondLine(tok[1], cond, text, tok[2] + 1)


def _target(p: Any, word: str) -> Any:
    if not p.has_value():
        raise p.error(f"{word} needs a label number or (expression)")
    return p.value()


def _args(p: Any) -> tuple[tuple[str, Any], ...]:
    """The ``{letter}{data}`` pairs after a GOSUB / CALL target."""
    out: list[tuple[str, Any]] = []
    while True:
        tok = p.peek()
        if tok is None or tok[0] != "word" or tok[1] not in _ARG_LETTERS:
            return tuple(out)
        start = p.i
        p.i += 1
        if not p.has_value():
            p.i = start
            return tuple(out)
        value = p.value()
        after = p.peek()
        if after is not None and after[0] == "op" and after[1] in _ASSIGNING:
            p.i = start  # ``M1=1`` after the call is an assignment, not an argument
            return tuple(out)
        out.append((tok[1], value))


def goto(p: Any, tok: Token) -> fl.Goto:
    return fl.Goto(_target(p, "GOTO"), tok[2] + 1)


def gosub(p: Any, tok: Token) -> fl.Gosub:
    target = _target(p, "GOSUB")
    return fl.Gosub(target, _args(p), tok[2] + 1)


def call(p: Any, tok: Token) -> fl.Call:
    num = p.peek()
    target = _target(p, "CALL")
    if target.const is not None and not 1 <= int(target.const) <= 32767:
        raise p.error("CALL: PROG number must be 1..32767", num)
    return fl.Call(target, _args(p), tok[2] + 1)


def code_call(p: Any, tok: Token, value: Any) -> fl.Call:
    """A G-, M-, T- or D-code (its value already read by the parser) and its arguments."""
    return fl.Call(value, _args(p), tok[2] + 1, tok[1])


def return_(p: Any, tok: Token) -> fl.Return:
    return fl.Return(tok[2] + 1)


def read(p: Any, tok: Token) -> fl.Read:
    """``READ(A,B,...)``: no blank between READ and ``(`` (TSRM p466)."""
    paren = p.peek()
    if paren is None or paren[0] != "op" or paren[1] != "(" or paren[2] != tok[3]:
        raise p.error("READ needs (letters) right after it", paren)
    p.take()
    letters: list[str] = []
    while True:
        t = p.take()
        if t[0] != "word" or len(t[1]) != 1 or t[1] not in _ARG_LETTERS:
            raise p.error("READ: expected a letter (not N or O)", t)
        letters.append(t[1])
        if p.at("op", ","):
            p.take()
            continue
        p.expect_op(")")
        return fl.Read(tuple(letters), tok[2] + 1)


def stop(p: Any, tok: Token) -> fl.Stop:
    return fl.Stop(tok[2] + 1)


def wait(p: Any, tok: Token) -> fl.Wait:
    return fl.Wait(tok[2] + 1)


def block_start(p: Any, tok: Token) -> fl.BlockStart:
    return fl.BlockStart(tok[2] + 1)


def block_stop(p: Any, tok: Token) -> fl.BlockStop:
    return fl.BlockStop(tok[2] + 1)


__all__ = [
    "block_start", "block_stop", "call", "code_call", "cond_line", "else_", "endif", "endwhile",
    "gosub", "goto", "if_", "read", "return_", "stop", "wait", "while_",
]  # fmt: skip
