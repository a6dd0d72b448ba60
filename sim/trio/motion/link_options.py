"""CAMBOX / MOVELINK ``link_options`` bits and MOVELINK's curved ramps, as data.

The bits (MC4 help text, CAMBOX-MD / MOVELINK-MD, spec §10.3, §11.9; bit 3 also MC206 TRM
p. 8-23):

=== ====== ===================================================== ==========================
bit value  meaning                                               here
=== ====== ===================================================== ==========================
0   1      start exactly at a MARK registration of the link axis not simulated (no registration)
1   2      start when the link axis reaches ``link_pos``         simulated
2   4      repeat automatically and bi-directionally; ended at   simulated
           the end of a cycle by REP_OPTION bit 1 (then cleared)
3   8      CAMBOX pattern mode (control block in the TABLE)      simulated (CAMBOX)
4   16     MOVELINK curved (S) ramps, shape in bits 10..12       simulated (MOVELINK)
5   32     link active only while the link axis moves positive   simulated
7   128    CAMBOX starts at ``offset_start`` in the link distance not simulated
8   256    start on MARKB                                        not simulated
9   512    start on R_MARK (``link_pos`` = channel)              not simulated
13  8192   follow the link axis' DPOS, not MPOS                  accepted: MPOS = DPOS here
14  16384  active from a rising threshold                        not simulated
=== ====== ===================================================== ==========================

Bits 10..12 (MOVELINK with bit 4): 0 sine, 1 power-9, 2 power-7, 3 power-5 polynomial, 4
linear; 5..7 unused. Their peak accelerations are 1.55 / 2.42 / 2.16 / 1.86 x the linear
ramp's (MOVELINK-MD); the ramps here are the smooth polynomials with those peaks (the
sine, and the 5th / 7th / 9th-order "smoothstep" speed curves, ``[INF]``), each covering half
the ramp's link distance times the speed change, as the linear ramp does.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from ..card.basic_errors import BasicError

START_AT_POS = 1 << 1
REPEAT = 1 << 2
PATTERN = 1 << 3
CURVED = 1 << 4
POSITIVE_ONLY = 1 << 5
FOLLOW_DPOS = 1 << 13

#: Bits each command accepts (the others of :data:`KNOWN` are refused as not simulated).
SIMULATED: dict[str, int] = {
    "CAMBOX": START_AT_POS | REPEAT | PATTERN | POSITIVE_ONLY | FOLLOW_DPOS,
    "MOVELINK": START_AT_POS | REPEAT | CURVED | POSITIVE_ONLY | FOLLOW_DPOS | (7 << 10),
}
#: Bits the manual defines: 0..5 and 7..14 (any other bit is a parameter error).
KNOWN = sum(1 << b for b in (*range(6), *range(7, 15)))

#: The speed-ramp shapes: integral F(x) of the normalised speed curve f(x), f(0)=0, f(1)=1,
#: F(1) = 1/2, by the code of bits 10..12.
RAMPS: dict[int, Callable[[float], float]] = {
    0: lambda x: x / 2.0 - math.sin(math.pi * x) / (2.0 * math.pi),  # sine
    1: lambda x: x**6 * (21.0 + x * (-60.0 + x * (67.5 + x * (-35.0 + 7.0 * x)))),  # power 9
    2: lambda x: x**5 * (7.0 + x * (-14.0 + x * (10.0 - 2.5 * x))),  # power 7
    3: lambda x: x**4 * (2.5 + x * (-3.0 + x)),  # power 5
    4: lambda x: 0.5 * x * x,  # linear
}


def linear_ramp(x: float) -> float:
    return 0.5 * x * x


def check_options(kind: str, options: float) -> int:
    """The integer options of ``kind``; BasicError for bits not defined or not simulated."""
    n = int(options)
    if n != options or n < 0 or n & ~KNOWN:
        raise BasicError(f"Parameter out of range: {kind} link_options {options:g}")
    missing = n & ~SIMULATED[kind]
    if missing:
        bits = ", ".join(str(b) for b in range(15) if missing >> b & 1)
        raise BasicError(f"{kind} link_options bit {bits} not simulated")
    if kind == "MOVELINK" and n & CURVED and (n >> 10) & 7 not in RAMPS:
        raise BasicError(f"{kind} link_options: curve {(n >> 10) & 7} is not defined")
    return n


def ramp_of(options: int) -> Callable[[float], float]:
    """MOVELINK's ramp shape for ``options`` (linear unless bit 4 is set)."""
    return RAMPS[(options >> 10) & 7] if options & CURVED else linear_ramp


__all__ = ["CURVED", "FOLLOW_DPOS", "PATTERN", "POSITIVE_ONLY", "RAMPS", "REPEAT",
           "START_AT_POS", "check_options", "ramp_of"]
