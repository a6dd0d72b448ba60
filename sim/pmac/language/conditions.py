"""The parts of a Turbo PMAC condition (``IF`` / ``WHILE`` / a PLC's ``AND`` / ``OR`` lines):
the comparators and how simple conditions combine (TUM p252; TSRM p23).

The parser reads conditions from a line's tokens (``_Parser.condition``); the builders of the
control-flow words (:mod:`.flow_words`) join the parenthesised groups of one line and the
PLC compiler those of continuation lines, all with :func:`any_of_all`.
"""

from __future__ import annotations

import operator
from collections.abc import Callable
from typing import Any, Final

#: A condition: a function of the variables and the coordinate system.
Cond = Callable[[Any, int], bool]
#: The comparators of a condition (TUM p252, TSRM p23); ``<=`` / ``>=`` / ``<>`` are not PMAC
#: syntax (``!>`` / ``!<`` / ``!=``).
COMPARATORS: dict[str, Callable[[float, float], bool]] = {
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
_NOT_COMPARATORS: Final = frozenset(["<>", ">=", "<=", "=="])


def any_of_all(groups: list[list[Cond]]) -> Cond:
    """OR over blocks of AND-ed conditions: AND binds tighter than OR, and evaluation stops
    at the first false condition of a block (TUM p252)."""
    if len(groups) == 1 and len(groups[0]) == 1:
        return groups[0][0]
    blocks = tuple(tuple(g) for g in groups)
    if len(blocks) == 1:
        only = blocks[0]
        return lambda v, c: all(f(v, c) for f in only)
    return lambda v, c: any(all(f(v, c) for f in g) for g in blocks)


__all__ = ["COMPARATORS", "Cond", "any_of_all"]
