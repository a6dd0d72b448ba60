"""On-line motor commands (addressed with ``#n``) and their parsing (TSRM p270-283; spec §11.9).

``J+`` ``J-`` ``J/`` ``J=`` ``J={pos}`` ``J^{d}`` ``J:{d}``, ``HM`` / ``HOME``, ``HMZ`` /
``HOMEZ``, ``K``, ``O{p}``, ``$``, ``$*``, and ``##n`` (the motor group CTRL-B/F/P/V report).
They are on-line only: with a buffer open they still act at once (TUM p46) — except that
``J-5`` there is a circle-vector word and ``O10`` a label, as in a program.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

#: Operators that make a ``J`` a jog command.
_JOG_OPS = frozenset(["+", "-", "/", "=", "^", ":"])


@dataclass(frozen=True, slots=True)
class Jog:
    """``J+`` ``J-`` ``J/`` ``J=`` (``value`` None: to the pre-jog position), ``J=pos``,
    ``J^d``, ``J:d``; ``command`` is the text without the value.

    ``variable``: ``J=*`` / ``J^*`` / ``J:*`` take the target or distance from the motor's
    variable jog register (Mxx72, ``L:$0000D7`` + $80 per motor, counts) when the command
    runs. ``trigger``: a definite jog written ``{jog}^{d}`` is a jog-until-trigger, ending
    ``d`` counts past the position captured at the trigger (PSRM p241; TSRM p282)."""

    command: str
    value: float | None = None
    variable: bool = False
    trigger: float | None = None


@dataclass(frozen=True, slots=True)
class Home:
    """``HM`` (search) or, with ``zero``, ``HMZ`` (the present position becomes zero)."""

    zero: bool = False


@dataclass(frozen=True, slots=True)
class Kill:
    """``K``: kill the addressed motor."""


@dataclass(frozen=True, slots=True)
class OpenLoop:
    """``O{p}``: open-loop output of ``percent`` % of Ixx69."""

    percent: float


@dataclass(frozen=True, slots=True)
class Enable:
    """``$``: close the loop; with ``absolute``, ``$*``: read the absolute position."""

    absolute: bool = False


@dataclass(frozen=True, slots=True)
class MotorGroup:
    """``##n`` selects motors 8n+1..8n+8 for CTRL-B/F/P/V; ``##`` reports it."""

    group: int | None


MOTOR_TYPES = (Jog, Home, Kill, OpenLoop, Enable)
#: Motors a list may name (Turbo PMAC: 32).
N_MOTORS_LIST = 32


@dataclass(frozen=True, slots=True)
class HomeList:
    """``HOME{n}[,{n}...]`` / ``HOMEZ{n}..{m}`` (``HM``, ``HMZ``): the program command with a
    motor list (TSRM ``HOME{list}`` program command ``[BK]``); each listed motor homes as
    ``#nHM`` would. In a motion program it is a lookahead break (spec §0 fact 10: DWELL,
    RAPID, HOME, PSET stop lookahead): when motion has stopped the motors start their home
    searches together and the program goes on once every one has ended
    (:mod:`motionsim.sim.pmac.modes.home`). On-line and in PLCs it starts them at once
    ``[INF]``."""

    motors: tuple[int, ...]
    zero: bool = False


def is_jog(parser: Any) -> bool:
    """Is the token after a ``J`` one that makes it a jog (rather than a vector word)?"""
    tok = parser.peek()
    if tok is None or tok[0] != "op" or tok[1] not in _JOG_OPS:
        return False
    if tok[1] == "-" and parser.open:
        nxt = parser.peek(1)
        return not (nxt is not None and (nxt[0] == "num" or nxt[1] == "("))
    return True


def parse_jog(parser: Any) -> Jog:
    """The rest of a jog after its ``J`` (the parser stands on the operator)."""
    op = parser.take()[1]
    if op in ("+", "-", "/"):
        return Jog("J" + op)
    tok = parser.peek()
    if tok is not None and tok[0] == "op" and tok[1] == "*":
        parser.take()  # J=* / J^* / J:*: the target or distance in Mxx72
        return Jog("J" + op, None, True, _trigger(parser))
    if op == "=" and not parser.has_value():
        return Jog("J=", None, False, _trigger(parser))
    value = parser.value()
    if value.const is None:
        raise parser.error(f"J{op} needs a constant", tok)
    return Jog("J" + op, float(value.const), False, _trigger(parser))


def _trigger(parser: Any) -> float | None:
    """The ``^{d}`` that makes a definite jog a jog-until-trigger (None without it)."""
    tok = parser.peek()
    if tok is None or tok[0] != "op" or tok[1] != "^":
        return None
    parser.take()
    at = parser.peek()
    value = parser.value()
    if value.const is None:
        raise parser.error("a jog-until-trigger's ^ needs a constant distance", at)
    return float(value.const)


__all__ = [
    "MOTOR_TYPES",
    "HomeList",
    "Enable",
    "Home",
    "Jog",
    "Kill",
    "MotorGroup",
    "OpenLoop",
    "is_jog",
    "parse_jog",
]


def home_word(p: Any, tok: tuple[str, str, int, int]) -> Home | HomeList:
    """Keyword-table builder: ``HM`` / ``HMZ`` (addressed motor) or, with a motor list,
    ``HOMEZ1,2,3`` / ``HOME1..4``."""
    zero = tok[1] in ("HMZ", "HOMEZ")
    if p.at("num"):
        return HomeList(p.number_list(1, N_MOTORS_LIST, "motor"), zero)
    return Home(zero=zero)
