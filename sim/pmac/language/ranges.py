"""Range and indirect variable commands (TSRM p328; TUM p243; PSRM p252-253; spec §12.4).

* ``{kind}{a}..{b}={expr}`` and ``{kind}{n},{count}[,{step}]={expr}`` assign one value to a
  set of variables: ``Q70..99=3540``; ``I5213,15,100=10`` sets I5213, I5313 ... I6613
  (``[INF]`` the same set the query form lists; Diamond's set-up files use it for Isx13,
  Isx20, Isx50 of every CS). Valid on-line and in PLC programs; the value is evaluated once.
* ``{kind}({expr})`` with no ``=`` is an indirect query (``P(P1+10)``): one data line, like
  ``P11``. A number outside 0..8191 is ERR003 ``[INF]``.

The range *queries* (``I100..105``, ``I130,4,100``) are the parser's
:class:`motionsim.sim.pmac.language.statements.VarQuery`.
"""

from __future__ import annotations

from dataclasses import dataclass

from .expressions import Expr


@dataclass(frozen=True, slots=True)
class RangeAssign:
    """``{kind}{numbers}={value}``: the same value to each of ``numbers``."""

    kind: str
    numbers: tuple[int, ...]
    value: Expr


@dataclass(frozen=True, slots=True)
class IndirectQuery:
    """``{kind}({expr})``: the value of the variable whose number ``index`` gives."""

    kind: str
    index: Expr
    #: Not a PLC statement (a query answers the host).
    in_program = False


def numbers(first: int, last: int | None, count: int | None, step: int) -> tuple[int, ...]:
    """The variable numbers of ``{first}..{last}`` or ``{first},{count},{step}``."""
    if last is not None:
        return tuple(range(first, last + 1))
    return tuple(first + step * k for k in range(count or 0))


__all__ = ["IndirectQuery", "RangeAssign", "numbers"]
