"""How much of a name counts: the significant characters of variable names and labels.

TJ1P-26 (Trajexia TJ1 Programming Manual, the MC2xx generation's OEM twin; spec trio.md §2.1,
§2.2): a label may be of any length, its first **15** characters are significant; a named local
variable's first **16** characters are significant. Two names that agree in those characters
are one name: ``machine_speed_limit_x`` and ``machine_speed_limit_y`` (16 characters alike) are
one variable, and two labels agreeing in their first 15 characters are one label defined twice.
The MC4xx / MC6xx manuals were not reachable on this point; the same figures are used on every
model ``[INF]``, and for the names MC4 declarations give (DIM, GLOBAL, CONSTANT, FUNCTION and
its parameters), which are variable names ``[INF]``. Keywords are matched in full, before this
applies: only a program's own names are cut.
"""

from __future__ import annotations

from typing import Final

#: Significant characters of a local variable name (TJ1P-26).
VARIABLE_CHARS: Final = 16
#: Significant characters of a label (TJ1P-26).
LABEL_CHARS: Final = 15


def variable(name: str) -> str:
    """The name a variable is known by: its first :data:`VARIABLE_CHARS` characters."""
    return name[:VARIABLE_CHARS]


def label(name: str) -> str:
    """The name a label is known by: its first :data:`LABEL_CHARS` characters."""
    return name[:LABEL_CHARS]


__all__ = ["LABEL_CHARS", "VARIABLE_CHARS", "label", "variable"]
