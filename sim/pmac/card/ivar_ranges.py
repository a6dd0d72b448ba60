"""Turbo PMAC I-variable value rules: limited ranges roll over, I41 locks whole sets.

Limited range (TUM p243; PMAC(1) PUM p148): assigning an out-of-range value to an
I-variable with a limited range is no error; the value is rolled into the range by modulo
arithmetic (truncation). The manual's example: I3 has the range 0..3 (4 values), so
``I3=5`` assigns 5 mod 4 = 1. For a range lo..hi of span hi - lo + 1 the stored value is
``lo + (v - lo) mod span``; every range kept here starts at 0 (below), so it is
``v mod (hi + 1)``, and a negative value comes in from the top (``I3=-1`` -> 3).

``[INF]`` the manual says nothing of fractions: "modulo arithmetic (truncation)" is read as
truncation toward zero first (``I3=2.7`` -> 2, ``I3=-1.5`` -> -1 -> 3).

The table holds the integer I-variables whose SRM ``Range:`` is a bit field, 0 .. 2^k - 1,
i.e. the registers where rolling over is what dropping the high bits does. Left out on
purpose: floats and full 24/48-bit words (nothing to roll over), and ranges that do not
start at 0 — the SRM itself says Ixx92 (range 1..8,388,607, TSRM p152) "should not be set
to 0", so 0 is storable and those ranges are advice, not storage limits ``[INF]``.

I41 I-variable lockout (TSRM p57): each set bit locks one set of I-variables — bit 0
I100..I4899 (motor setup), bit 1 I5100..I6699 (coordinate systems), bit 2 I6800..I7999
(MACRO / Servo ICs), bit 3 I8000..I8191 (conversion table). A command that sets a locked
I-variable, on-line or from a buffered program, is ignored without an error. ``[INF]``
``I{n}=*`` is such a command too; I41 itself and the other global I-variables are never
locked.
"""

from __future__ import annotations

import math
from typing import Final

#: ``I{n}: (hi, source)`` — the limited ranges 0..hi applied on assignment.
_GLOBAL: Final[dict[int, tuple[int, str]]] = {
    3: (3, "TSRM p37"),
    4: (3, "TSRM p38"),
    5: (3, "TSRM p39"),
    6: (3, "PSRM p25 [INF] Turbo page not retrieved"),
    9: (3, "TSRM p42"),
    40: (65_535, "TSRM p57"),
    41: (15, "TSRM p57"),
    42: (1, "TSRM p58"),
    43: (3, "TSRM p58"),
    59: (3, "TSRM p65"),
    60: (15, "TSRM p65"),
    63: (1, "TSRM p67"),
    64: (1, "TSRM p67"),
    67: (0x3FFFF, "TSRM p68"),
    5000: (3, "TSRM p170"),
}

#: Motor ``Ixx{nn}`` (all 32 motors).
_MOTOR: Final[dict[int, tuple[int, str]]] = {
    80: (7, "TSRM p136"),
}

#: Coordinate-system ``Isx{nn}`` (all 16 systems).
_CS: Final[dict[int, tuple[int, str]]] = {
    13: (255, "TSRM p177 (spec pmac.md §9.2)"),
    21: (15, "TSRM p181"),
    50: (1, "TSRM p181"),
    92: (1, "TSRM p184-190 (spec pmac.md §9.3)"),
}


def _build() -> dict[int, tuple[int, str]]:
    out = dict(_GLOBAL)
    for xx in range(1, 33):
        out.update({100 * xx + nn: r for nn, r in _MOTOR.items()})
    for cs in range(1, 17):
        out.update({5000 + 100 * cs + nn: r for nn, r in _CS.items()})
    return out


#: Every limited-range I-variable: number -> (hi, source); the range is 0..hi.
RANGES: Final[dict[int, tuple[int, str]]] = _build()

#: I41 bit -> the I-variables it locks (TSRM p57).
LOCKOUT_SETS: Final[tuple[range, ...]] = (
    range(100, 4900),
    range(5100, 6700),
    range(6800, 8000),
    range(8000, 8192),
)


def roll_over(n: int, value: float) -> float:
    """The value I{n} holds after ``I{n}={value}``: rolled into its range if it has one."""
    r = RANGES.get(n)
    if r is None:
        return value
    hi, _source = r
    return float(math.trunc(value) % (hi + 1))


def locked(n: int, i41: float) -> bool:
    """Whether I41 = ``i41`` locks I{n} against assignment."""
    bits = int(i41)
    if not bits:  # the factory I41 = 0: nothing locked (the common case, kept cheap)
        return False
    return any(bits >> b & 1 and n in s for b, s in enumerate(LOCKOUT_SETS))


__all__ = ["LOCKOUT_SETS", "RANGES", "locked", "roll_over"]
