"""Factory defaults of I0..I8191 and which I-variables are reported in hex (I9 bit 1).

The card modelled: a Turbo PMAC that identifies as a Geo Brick (``CID`` 603382) with 8 local
axes and no MACRO ICs. Its I-variable defaults are those of the factory dump that
dls-pmacanalyse ships (``factorySettings_pmac.pmc``: a MACRO Turbo PMAC2 reset with
``$$$***``, spec pmac.md §11.6), written here as rules per variable block, with these
departures (``MANUAL_OVERRIDES`` / ``CARD_OVERRIDES``):

* where the dump and the Turbo SRM disagree the manual wins (spec §11.6): I5 = 1 (TSRM p39),
  I17 = 10 (TSRM p46), I64 = 0 (TSRM p67), I5049 = 1 (TSRM p171: gather every servo cycle),
  Isx98 = 1000 (TSRM p193);
* I4 = 0: no checksums (the dump's I4 = 1 is the capture connection's, spec §11.6 ``[INF]``);
* I10 = 3 713 707 (442.708 µs servo cycle), the simulator's clock (spec §6) on which all of its
  timing is calibrated; the dump has 3 713 991 and TSRM p216 quotes 3 713 992 for the Turbo
  PMAC2 default clock, 0.008 % apart ``[INF]``;
* Ixx00 = 1 for motors 1–8: a Geo Brick's 8 local axes are activated (the dump's MACRO card
  activates motor 1 only) ``[INF]``; motors 9–32 stay 0 (``R`` in a CS with one of them
  answers ERR013, :mod:`motionsim.sim.pmac.lookahead.start_checks`);
* I7000–I7199: the Servo-IC clock and channel variables of those 8 axes
  (:mod:`.servo_ic`), all 0 in the dump;
* I20 = $0: this card has no MACRO IC (I20–I23 are found by auto-detection at
  re-initialisation, TSRM p50; dls-pmaclib and dls-pmacanalyse count 8 axes per non-zero one);
* live registers (Isx11/Isx12 timers, I4909) start at 0.

``tests/sim/pmac/test_factory_defaults.py`` reads the dump from the installed package and
checks every value against these rules and exceptions.

Hex reporting (TUM p46; PSRM p28; spec §11.5): with I9 bit 1 set, the *address-type*
I-variables answer ``$hhhhhh`` (upper case, no padding); the list is the set the dump (taken
with I9 = 2) reports with ``$``. ``[INF]`` MACRO ICs 1–3 use the same offsets as IC 0.
"""

from __future__ import annotations

from typing import Final

from ...timing import pmac_servo_period_s
from . import servo_ic

N_IVARS: Final = 8192

#: Global I0..I99 (dump values; hex ones written in hex).
_GLOBAL: Final[dict[int, float]] = {
    2: 1, 3: 2, 6: 1, 8: 2, 9: 2, 10: 3_713_991, 16: 5, 17: 5, 18: 10, 19: 6807,
    20: 0x78400, 24: 0x60000, 52: 7, 53: 12, 54: 12, 58: 1, 60: 15, 61: 8, 63: 1, 64: 1,
    68: 15, 79: 32, 90: 0x39, 91: 0x4, 92: 0xFF, 93: 0x7F, 94: 0xA0, 95: 0x7, 96: 0xA1,
    98: 0x60, 99: 0x30,
}  # fmt: skip

#: Motor Ixx{nn} that are the same for all 32 motors (Ixx15/16/17/19 cts/ms(²), Ixx21 ms).
_MOTOR: Final[dict[int, float]] = {
    5: 0x35C0, 7: 96, 8: 96, 9: 96, 11: 32000, 12: 16000, 15: 0.25, 16: 32, 17: 0.015625,
    19: 0.015625, 21: 50, 22: 32, 23: 32, 28: 160, 30: 2000, 31: 1280, 32: 1280, 34: 1,
    63: 4_194_304, 65: 16, 66: 6527, 67: 4_194_304, 69: 20480, 70: 1, 71: 1000, 72: 1365,
    87: 64, 92: 10,
}  # fmt: skip

#: Coordinate-system Isx{nn}, all 16 systems (Isx93 below: one per CS).
_CS: Final[dict[int, float]] = {
    88: 50, 89: 1000, 90: 1000, 94: 1644, 95: 1644, 99: 0.9998474121,
}  # fmt: skip

#: MACRO IC 0 (I6800..I6849) and status registers I4900..I4908 as the dump has them.
_OTHER: Final[dict[int, float]] = {
    4902: 0x1, 4903: 0x1, 4904: 0x8006, 4908: 0x1C000,
    6800: 6527, 6802: 3, 6803: 2258, 6804: 15, 6805: 0x7FFFC0, 6806: 0xFFFFFE, 6810: 7,
    6812: 1, 6820: 7, 6822: 1, 6840: 0x4000,
}  # fmt: skip

#: Motors 1–8 of the dump's card drive MACRO IC 0 nodes; its flag registers (Ixx25).
_FLAG_OFFSETS: Final = (0, 1, 4, 5, 8, 9, 12, 13)
_UNUSED_ADDRESS: Final = 0x35E5

#: Where the Turbo SRM and the dump disagree: the manual's value (spec §11.6).
MANUAL_OVERRIDES: Final[dict[int, tuple[float, str]]] = {
    5: (1, "TSRM p39"),
    17: (10, "TSRM p46"),
    64: (0, "TSRM p67"),
    5049: (1, "TSRM p171"),
    **{5000 + 100 * cs + 98: (1000, "TSRM p193") for cs in range(1, 17)},
}

#: The simulator's servo clock (I10, spec §6).
SERVO_CLOCK_I10: Final = 3_713_707

#: Where this card is not the dump's card (see the module docstring).
CARD_OVERRIDES: Final[dict[int, tuple[float, str]]] = {
    4: (0, "no checksums [INF]"),
    10: (SERVO_CLOCK_I10, "the simulator's servo clock (spec §6)"),
    20: (0, "no MACRO IC on this card"),
    **{100 * xx: (1, "a Geo Brick activates its 8 local axes [INF]") for xx in range(2, 9)},
    **{n: (v, "Servo ICs 0 and 1 of the 8 local axes (servo_ic.py)")
       for n, v in servo_ic.ivars(pmac_servo_period_s(SERVO_CLOCK_I10)).items() if v},
    4909: (0, "live register"),
    **{5000 + 100 * cs + nn: (0, "live timer") for cs in range(1, 17) for nn in (11, 12)},
}


def _motor_block(xx: int) -> dict[int, float]:
    base = 100 * xx
    out = {base + nn: v for nn, v in _MOTOR.items()}
    out[base + 0] = 1 if xx == 1 else 0
    node = 0x78420 + 4 * (xx - 1) if xx <= 8 else _UNUSED_ADDRESS
    out[base + 2] = out[base + 83] = node
    out[base + 3] = out[base + 4] = 0x3502 + 2 * (xx - 1) if xx <= 16 else 0x3521
    out[base + 24] = 0x40001 if xx <= 16 else 0
    out[base + 25] = 0x3440 + _FLAG_OFFSETS[xx - 1] if xx <= 8 else _UNUSED_ADDRESS
    return out


def _build() -> tuple[float, ...]:
    values = [0.0] * N_IVARS
    table: dict[int, float] = dict(_GLOBAL)
    for xx in range(1, 33):
        table.update(_motor_block(xx))
    for cs in range(1, 17):
        base = 5000 + 100 * cs
        table.update({base + nn: v for nn, v in _CS.items()})
        table[base + 93] = 0x2000 + 0x100 * (cs - 1)
    table.update({n: 0x78800 for n in range(5061, 5077)})
    table.update(_OTHER)
    for k in range(8):  # encoder conversion table: one 2-line MACRO entry per node
        table[8000 + 2 * k] = 0x2F8420 + 4 * k
        table[8001 + 2 * k] = 0x18000
    for n, (v, _why) in (MANUAL_OVERRIDES | CARD_OVERRIDES).items():
        table[n] = v
    for n, v in table.items():
        values[n] = float(v)
    return tuple(values)


#: I0..I8191 after ``$$$***``.
FACTORY: Final[tuple[float, ...]] = _build()


def _hex_set() -> frozenset[int]:
    out: set[int] = {20, 21, 22, 23, 24, 37, 67, *range(69, 78), *range(90, 100)}
    for xx in range(1, 33):
        out.update(100 * xx + nn for nn in (2, 3, 4, 5, 10, 24, 25, 42, 43, 55, 81, 82, 83,
                                            84, 91, 95))  # fmt: skip
    out.update(5000 + 100 * cs + 93 for cs in range(1, 17))
    out.update((*range(4900, 4905), 4908))
    out.update((*range(5001, 5049), 5050, 5051, *range(5061, 5077), *range(5081, 5097)))
    for ic in range(4):
        out.update(6800 + 50 * ic + nn for nn in (5, 6, 40, 41))
    out.update(range(8000, 8192))
    return frozenset(out)


#: The address-type I-variables: reported ``$hhhhhh`` when I9 bit 1 is set.
HEX_IVARS: Final[frozenset[int]] = _hex_set()


def default_i(n: int) -> float:
    """The factory value of I{n} (0 outside 0..8191)."""
    return FACTORY[n] if 0 <= n < N_IVARS else 0.0


__all__ = ["CARD_OVERRIDES", "FACTORY", "HEX_IVARS", "MANUAL_OVERRIDES", "N_IVARS", "default_i"]
