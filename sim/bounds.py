"""Bounds on every time, rate and size a client can set: finite, documented, checked in one place.

A value outside its bound is refused before anything changes (``InvalidValue`` naming the
field, a 422 over REST), so no controller is left holding an ``inf`` time or a size that
exhausts memory. The REST schemas show the same bounds (``ge`` / ``le`` in ``/openapi.json``)
and the ``config`` field's description lists the controller ones.

Where the manual gives a range it is cited; the rest are ``[INF]`` limits chosen to be far
beyond any real use and small enough that the simulation stays finite and fast.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from .errors import InvalidValue


@dataclass(frozen=True, slots=True)
class Bound:
    """``low <= value <= high`` (``low_open``: ``low < value``); ``integer``: whole numbers."""

    low: float
    high: float
    unit: str = ""
    low_open: bool = False
    integer: bool = False

    def check(self, value: Any, field: str) -> float:
        """``value`` as a float, or :class:`InvalidValue` naming ``field`` and the bound."""
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise InvalidValue(f"{field} must be a number, got {value!r}", field=field)
        if not math.isfinite(value):
            raise InvalidValue(f"{field} must be finite, got {value!r}", field=field)
        low_ok = value > self.low if self.low_open else value >= self.low
        if not (low_ok and value <= self.high):
            raise InvalidValue(f"{field} must be {self.describe()}, got {value!r}", field=field)
        if self.integer and not float(value).is_integer():
            raise InvalidValue(f"{field} must be a whole number, got {value!r}", field=field)
        return float(value)

    def describe(self) -> str:
        op = "<" if self.low_open else "<="
        unit = f" {self.unit}" if self.unit else ""
        return f"{_fmt(self.low)} {op} x <= {_fmt(self.high)}{unit}"


def _fmt(x: float) -> str:
    return str(int(x)) if float(x).is_integer() and abs(x) < 1e15 else repr(x)


#: Any finite number.
FINITE = Bound(-math.inf, math.inf)

#: Clock and request times (app/ and api/).
CLOCK_FACTOR = Bound(1e-3, 1e4, "simulated s per wall s")  # [INF]
ADVANCE_SECONDS = Bound(0, 1e6, "s simulated")  # [INF] ~11.6 simulated days per request
TIMEOUT_SECONDS = Bound(0, 1e6, "s simulated")  # [INF]

#: PMAC controller config.
PMAC_CONFIG: dict[str, Bound] = {
    "servo_hz": Bound(100, 100_000, "Hz"),  # [INF] Turbo PMAC servo clocks run ~1-20 kHz
    "background_cycles": Bound(1, 100_000, "background cycles", integer=True),  # [INF]
    "i10": Bound(0, 8_388_607, "1/8388608 ms", low_open=True, integer=True),  # Turbo SRM I10
    "i8": Bound(0, 255, "servo cycles", integer=True),  # Turbo SRM I8: 0..255
}
#: PMAC ``cpu_<name>_us`` processor-time costs.
PMAC_CPU_COST = Bound(0, 10_000, "us")  # [INF]

#: Trio controller config (defaults in sim/trio/controller.py).
TRIO_CONFIG: dict[str, Bound] = {
    "servo_period_ms": Bound(0.05, 10, "ms"),  # [INF] SERVO_PERIOD 125 us .. 2 ms on MC4xx
    "axes": Bound(1, 64, "axes", integer=True),  # MC664: up to 64 axes [BK]
    "processes": Bound(1, 32, "processes", integer=True),  # MC664: 22 processes [BK]
    "statement_us": Bound(0, 100_000, "us", low_open=True),  # [INF]
    "vr_count": Bound(1, 65_536, "VR() variables", integer=True),  # MC4xx: 65 536 VR [BK]
    "table_size": Bound(1, 4_000_000, "TABLE() values", integer=True),  # [INF]
    "ethercat_slaves": Bound(0, 256, "EtherCAT slaves", integer=True),  # [INF]
}
#: Trio axis parameters (speed, accel, decel, creep, units) and move arguments.
TRIO_RATE = Bound(0, 1e12, "units (per s, per s^2)", low_open=True)  # [INF]
TRIO_DISTANCE = Bound(-1e12, 1e12, "user units")  # [INF]
#: UNITS, encoder edges per user unit: at least 1e-9, so that a distance held in whole edges
#: (REP_DIST, ...) reads back finite in user units; a denormal UNITS made them infinite [INF].
TRIO_UNITS = Bound(1e-9, 1e12, "edges per user unit")  # [INF]


def describe(table: dict[str, Bound]) -> str:
    """``"servo_hz: 100 <= x <= 100000 Hz; ..."`` for a schema description."""
    return "; ".join(f"{name}: {bound.describe()}" for name, bound in table.items())


__all__ = ["ADVANCE_SECONDS", "CLOCK_FACTOR", "FINITE", "PMAC_CONFIG", "PMAC_CPU_COST",
           "TIMEOUT_SECONDS", "TRIO_CONFIG", "TRIO_DISTANCE", "TRIO_RATE", "TRIO_UNITS", "Bound",
           "describe"]
