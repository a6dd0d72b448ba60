"""Turbo PMAC variables: I (setup), P (global), Q (per coordinate system), M (I/O pointers).

* I0..8191 start at the card's factory defaults (:mod:`motionsim.sim.pmac.card.factory`);
  ``I{n}=*`` restores one. Every I-variable assignment (on-line, PLC, motion program, REST,
  config) follows the card's value rules (:mod:`motionsim.sim.pmac.card.ivar_ranges`): a value
  outside a limited range rolls over into it (``I3=5`` -> 1, TUM p243), and a write to a
  set that I41 locks is ignored, no error (TSRM p57).
  Coordinate-system I-variables are ``Isx`` = I(5000 + 100·x + nn), e.g. I5113 = Isx13 of
  CS 1; motor I-variables ``Ixx`` = I(100·xx + nn), e.g. I115 = Ixx15 of motor 1.
* P0..8191 are global, Q0..8191 have one bank per coordinate system, M0..8191 are the
  M-variables: defined ones read and write card memory through their definitions
  (:mod:`motionsim.sim.pmac.card.mvars`), the others are plain values. Every M-variable write is
  an ``mvar`` event (``sync`` tells whether it came from
  a synchronous ``==``/``&=``/``|=``/``^=`` assignment).
* ``[INF]`` M-variables are treated as integer targets (the manual's ``M1=10*2/3`` gives 7),
  so a written value is rounded half away from zero. P/Q/I keep floats.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from ...errors import NotFound
from .factory import HEX_IVARS, default_i
from .ivar_ranges import locked, roll_over
from .mvars import MVariables
from .timers import TIMER_NUMBERS, CountdownTimers, timer_cs

N_VARS = 8192
N_CS = 16
N_MOTORS = 32

def format_ivar(n: int, value: float, i9: int) -> str:
    """The value of I{n} as a query reports it: ``$hhhhhh`` (upper case, no padding) for an
    address-type variable when I9 bit 1 is set (TUM p46; spec §11.5), else decimal."""
    if int(i9) & 2 and n in HEX_IVARS and value == int(value):
        return f"${int(value) & 0xFFFFFFFFFFFF:X}"
    return format_value(value)


def isx(cs: int, nn: int) -> int:
    """The number of coordinate-system variable Isx{nn} of CS ``cs`` (Isx13 of CS 1 -> 5113)."""
    return 5000 + 100 * cs + nn


def ixx(motor: int, nn: int) -> int:
    """The number of motor variable Ixx{nn} of motor ``motor`` (Ixx15 of motor 1 -> 115)."""
    return 100 * motor + nn


def format_value(v: float) -> str:
    """A value as the controller reports it: integers without a point, else up to 10
    significant digits with no trailing zeros (``6.666666667``) ``[INF]``."""
    if v == int(v) and abs(v) < 1e15:
        return str(int(v))
    s = f"{v:.10g}"
    if "e" in s:
        s = f"{v:.10f}".rstrip("0").rstrip(".")
    return s


def _round_m(v: float) -> float:
    return float(math.floor(abs(v) + 0.5) * (1 if v >= 0 else -1))


MWriteHook = Callable[[int, float, bool], None]


class Variables:
    """The variable store of one controller.

    Args:
        on_m_write: called ``(n, value, sync)`` after every M-variable write (emits ``mvar``).
    """

    def __init__(self, on_m_write: MWriteHook) -> None:
        self.i: dict[int, float] = {}
        self.p: dict[int, float] = {}
        self.q: dict[tuple[int, int], float] = {}
        self.m: dict[int, float] = {}
        #: Undefined L-variables (compiled PLCs' integers, no ``L{n}->``) as plain values.
        self.l: dict[int, float] = {}
        #: M-variable definitions and the memory they point into.
        self.mvars = MVariables()
        self._on_m_write = on_m_write
        #: The Isx11/Isx12 countdown timers, once the controller gives them its servo clock.
        self.timers: CountdownTimers | None = None
        #: Bumped on every I-variable change, so users may cache derived settings.
        self.version = 0
        self.reset()

    def reset(self) -> None:
        """Factory defaults: I-variables to defaults, P/Q/M to 0."""
        self.i = {}
        self.version += 1
        self.p.clear()
        self.q.clear()
        self.m.clear()
        self.l.clear()
        self.mvars.clear()
        if self.timers is not None:
            self.timers.clear()

    # -- reading --------------------------------------------------------------------------

    def I(self, n: int) -> float:  # noqa: E743, N802 - the controller's own name
        if n in TIMER_NUMBERS and self.timers is not None:
            t = self.timers.read(n, timer_cs(n) <= self.I(68) + 1)
            if t is not None:
                return t
        v = self.i.get(n)
        return default_i(n) if v is None else v

    def read(self, kind: str, n: int, cs: int = 1) -> float:
        """Value of ``kind`` (I P Q M) number ``n``; Q from the bank of ``cs``."""
        if not 0 <= n < N_VARS:
            return 0.0
        if kind == "P":
            return self.p.get(n, 0.0)
        if kind == "Q":
            return self.q.get((cs, n), 0.0)
        if kind == "M":
            d = self.mvars.defs.get(n)
            return self.m.get(n, 0.0) if d is None else self.mvars.read(d)
        if kind == "L":
            d = self.mvars.ldefs.get(n)
            return self.l.get(n, 0.0) if d is None else self.mvars.read(d)
        return self.I(n)

    def angles_in_degrees(self) -> bool:
        return self.I(15) == 0

    # -- writing --------------------------------------------------------------------------

    def write(self, kind: str, n: int, value: float, cs: int = 1, sync: bool = False) -> None:
        """Assign; out-of-range numbers are ignored (the controller wraps, we drop) ``[INF]``."""
        if not 0 <= n < N_VARS:
            return
        if kind == "P":
            self.p[n] = value
        elif kind == "Q":
            self.q[(cs, n)] = value
        elif kind == "M":
            d = self.mvars.defs.get(n)
            if d is None:  # self-referenced: a plain variable
                value = _round_m(value)
                self.m[n] = value
            else:
                value = self.mvars.write(d, value)
            self._on_m_write(n, value, sync)
        elif kind == "L":  # a compiled PLC's L-variable: through its definition, or plain
            d = self.mvars.ldefs.get(n)
            if d is None:
                self.l[n] = float(_round_m(value))
            else:
                self.mvars.write(d, value)
        elif not locked(n, self.I(41)):
            if n in TIMER_NUMBERS and self.timers is not None:
                value = self.timers.write(n, value)
            self.i[n] = roll_over(n, value)
            self.version += 1

    def set_default(self, n: int) -> None:
        """``I{n}=*`` (ignored, like an assignment, while I41 locks I{n} ``[INF]``)."""
        if locked(n, self.I(41)):
            return
        self.i.pop(n, None)
        self.version += 1


def parse_name(name: str) -> tuple[str, int, int]:
    """``"I16"`` -> ("I", 16, cs 1); ``"Q3"`` -> ("Q", 3, 1); ``"&2Q3"`` -> ("Q", 3, 2).

    Raises:
        NotFound: not a PMAC variable name.
    """
    s = name.strip().upper()
    cs = 1
    if s.startswith("&"):
        j = 1
        while j < len(s) and s[j].isdigit():
            j += 1
        if j == 1:
            raise NotFound(f"no such variable {name!r}")
        cs = int(s[1:j])
        s = s[j:]
    if len(s) < 2 or s[0] not in "IPQM" or not s[1:].isdigit():
        raise NotFound(f"no such variable {name!r}")
    n = int(s[1:])
    if n >= N_VARS or not 1 <= cs <= N_CS:
        raise NotFound(f"no such variable {name!r}")
    return s[0], n, cs


__all__ = [
    "N_CS",
    "N_MOTORS",
    "Variables",
    "default_i",
    "format_ivar",
    "format_value",
    "isx",
    "ixx",
    "parse_name",
]
