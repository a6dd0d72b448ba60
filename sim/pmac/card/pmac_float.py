"""The Turbo PMAC's 48-bit floating-point word (``L:`` memory) as hosts write it.

Layout (spec pmac.md §12.7, from the EPICS driver's ``doubleToPMACFloat``, EPH l. 415–480):
the top 36 bits hold the mantissa, the low 12 bits the exponent offset by $800. For a value
``v ≠ 0``: ``|v| = m · 2**e`` with ``1 ≤ m < 2``; stored exponent ``e + $800``; mantissa
``floor(m · 2**34)``, and for ``v < 0`` its ones' complement in 36 bits ($FFFFFFFFF − mantissa),
so bit 47 is the sign. 0.0 is the all-zero word. A 48-bit word is the X word (high 24 bits)
and the Y word (low 24 bits) of one address. The precision is 2**-34 relative (≈ 6e-11).
"""

from __future__ import annotations

import math
from typing import Final

MASK48: Final = (1 << 48) - 1
_MANT_MAX: Final = (1 << 36) - 1
_BIAS: Final = 0x800


def encode(value: float) -> int:
    """``value`` as the 48-bit word (0 for 0.0; not-finite values are refused).

    Raises:
        ValueError: ``value`` is NaN or infinite, or its exponent is outside ±2047.
    """
    if value == 0.0:
        return 0
    if not math.isfinite(value):
        raise ValueError(f"{value} has no 48-bit PMAC float")
    m, e = math.frexp(abs(value))  # abs = m * 2**e with 0.5 <= m < 1
    e -= 1  # 1 <= 2m < 2
    if not -_BIAS <= e < _BIAS:
        raise ValueError(f"{value} is outside the 48-bit PMAC float's range")
    mantissa = int(m * 2.0**35)  # (2m) * 2**34, truncated as the host does
    if value < 0:
        mantissa = _MANT_MAX - mantissa
    return (mantissa << 12) | (e + _BIAS)


def decode(raw: int) -> float:
    """The value of a 48-bit word."""
    raw &= MASK48
    if raw == 0:
        return 0.0
    mantissa = raw >> 12
    e = (raw & 0xFFF) - _BIAS
    if mantissa >> 35:
        return -math.ldexp(_MANT_MAX - mantissa, e - 34)
    return math.ldexp(mantissa, e - 34)


__all__ = ["MASK48", "decode", "encode"]
