"""Builders of the parser's own command words (rows of :mod:`.keywords`): buffer management,
reports, motor words and the motion-program words that are not control flow.

Each takes the parser (:class:`motionsim.sim.pmac.language.parser._Parser`) positioned after
the keyword and the keyword's token, and returns one statement.
"""

from __future__ import annotations

from typing import Any

from ..card import card_commands, comp_tables
from . import card_words, list_words
from . import motor_statements as motor_st
from . import plc_statements as plc_st
from . import statements as st
from .object_words import OBJECTS

Token = tuple[str, str, int, int]


def _object(p: Any, keyword: str, tok: Token) -> tuple[str, Token]:
    """The object word after ``keyword`` (long form); a valid but not simulated one raises
    the parse error that names it (``not_simulated``). The objects are those of the
    keyword row the parser is building (``p.row``)."""
    what = p.take()
    name = OBJECTS.get(what[1]) if what[0] == "word" else None
    row = p.row
    if name is None or row is None or name not in row.objects:
        objs = ", ".join(o for o, ok in row.objects.items() if ok) if row else ""
        raise p.error(f"{keyword} what? ({objs})", what)
    if not row.objects[name]:
        raise p.not_simulated(f"{keyword} {name}", tok)
    return name, what


def define(p: Any, tok: Token) -> Any:
    name, _ = _object(p, "DEFINE", tok)
    if name == "UBUFFER":
        return card_words.define_ubuffer(p)
    if name == "ROTARY":
        return st.DefineRotary(p.integer())
    if name == "GATHER":
        return st.DefineGather(p.integer() if p.at("num") else None)
    if name == "COMP":
        return comp_tables.parse_define(p)
    segments = p.integer()
    if not p.at("op", ","):
        raise p.error("DEFINE LOOKAHEAD needs {segments},{outputs}")
    p.take()
    return st.DefineLookahead(segments, p.integer())


def delete(p: Any, tok: Token) -> Any:
    name, _ = _object(p, "DELETE", tok)
    if name == "ALL":
        return card_words.delete_all(p)
    if name == "ROTARY":
        return st.DeleteRotary()
    if name == "GATHER":
        return st.DeleteGather()
    if name == "COMP":
        return comp_tables.DeleteComp()
    if name == "TRACE":
        return card_words.delete_trace(p)
    if name == "PLCC":
        if not p.at("num"):
            return plc_st.DeletePlcc(tuple(range(plc_st.N_PLCS)))
        return plc_st.DeletePlcc(p.number_list(0, plc_st.N_PLCS - 1, "PLCC"))
    return st.DeleteLookahead()


def open_(p: Any, tok: Token) -> Any:
    name, _ = _object(p, "OPEN", tok)
    if name == "ROTARY":
        return st.OpenRotary()
    if name in ("PLC", "PLCC"):
        return plc_st.OpenPlc(p.plc_number(), compiled=name == "PLCC")
    if name in ("FORWARD", "INVERSE"):
        return card_words.open_kinematic(name)
    num = p.peek()
    n = p.integer()
    if not 1 <= n <= 32767:
        raise p.error("PROG number must be 1..32767", num)
    return st.OpenProgram(n)


def close(p: Any, tok: Token) -> Any:
    return st.Close()


def clear(p: Any, tok: Token) -> Any:
    return p.clear()


def list_(p: Any, tok: Token) -> Any:
    nxt = p.peek()
    if nxt is not None and nxt[0] == "word":
        name = OBJECTS.get(nxt[1])
        row = p.row
        if name is not None and row is not None and row.objects.get(name) is False:
            raise p.not_simulated(f"LIST {name}", tok)
    return list_words.parse(p)


def gather(p: Any, tok: Token) -> Any:
    """``GATHER`` / ``GATHER TRIGGER`` (:mod:`motionsim.sim.pmac.tasks.gather`)."""
    nxt = p.peek()
    if nxt is not None and nxt[0] == "word" and OBJECTS.get(nxt[1]) == "TRIGGER":
        p.take()
        return st.Gather(trigger=True)
    return st.Gather()


def endgather(p: Any, tok: Token) -> Any:
    return st.EndGather()


def mflush(p: Any, tok: Token) -> Any:
    return st.MFlush()


def save(p: Any, tok: Token) -> Any:
    return card_commands.Save()


def enable(p: Any, tok: Token) -> Any:
    nxt = p.peek()
    compiled = nxt is not None and nxt[1] == "PLCC"
    return plc_st.EnablePlc(p.plc_list(), tok[1] in ("ENABLE", "ENA"), compiled)


def query(p: Any, tok: Token) -> Any:
    return st.Query("VER" if tok[1] in ("VERSION", "VER") else tok[1])


def home(p: Any, tok: Token) -> Any:
    return motor_st.Home(zero=tok[1] in ("HMZ", "HOMEZ"))


def move_mode(p: Any, tok: Token) -> Any:
    p.spline_line = False
    return st.MoveMode("LINEAR" if tok[1] in ("LINEAR", "LIN") else "RAPID")


def _one_or_two(p: Any, word: str) -> int:
    n = p.integer()
    if n not in (1, 2):
        raise p.error(f"{word}1 or {word}2", p.toks[p.i - 1])
    return n


def circle(p: Any, tok: Token) -> Any:
    n = _one_or_two(p, "CIRCLE")
    p.spline_line = False
    return st.MoveMode(f"CIRCLE{n}")


def spline(p: Any, tok: Token) -> Any:
    n = _one_or_two(p, "SPLINE")
    p.spline_line = True
    return st.MoveMode(f"SPLINE{n}")


def pvt(p: Any, tok: Token) -> Any:
    p.spline_line = False
    return st.PvtMode(p.pvt_time())


def pset(p: Any, tok: Token) -> Any:
    return st.PSet(p.pset_axes())


def axis_mode(p: Any, tok: Token) -> Any:
    return st.AxisMode(tok[1] == "INC", p.axis_list(radius=True))


def modal(p: Any, tok: Token) -> Any:
    return st.Modal(tok[1], p.value())


def dwell(p: Any, tok: Token) -> Any:
    return st.Dwell(p.value())


def delay(p: Any, tok: Token) -> Any:
    return st.Delay(p.value())


def message(p: Any, tok: Token) -> Any:
    s = p.peek()
    if s is None or s[0] != "str":
        raise p.error(f'{tok[1]} needs "text"')
    p.i += 1
    return st.Message(tok[1], s[1][1:-1])


__all__ = [
    "axis_mode", "circle", "clear", "close", "define", "delay", "delete", "dwell", "enable",
    "home", "list_", "message", "mflush", "modal", "move_mode", "open_", "pset", "pvt", "query",
    "save", "spline",
]  # fmt: skip
