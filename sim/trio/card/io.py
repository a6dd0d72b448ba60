"""The controller's digital and analogue I/O image: what IN, OP, READ_OP and AIN see.

Trio BASIC (TRM chapter 8 "Input / Output Commands", spec §2.3: ``IN(n)``, ``OP(n,ON/OFF)``,
``AIN(n)`` in M224-327 and real programs):

* ``OP(n, v)`` switches output n on (v non-zero) or off; ``OP(pattern)`` with one argument
  writes outputs 8.. from the pattern's bits (bit 0 = output 8), 16 outputs ``[BK]``;
* ``READ_OP(n)`` (and ``OP(n)`` used as a value, which the simulator accepts ``[INF]``) reads
  output n: 1 = ON, 0 = OFF;
* ``IN(n)`` reads input n (1 / 0); ``IN(a, b)`` inputs a..b as a binary number with input a
  as bit 0 ``[BK]``; inputs read 0 until set from outside (``PUT /variables/IN(n)``);
* ``AIN(n)`` reads 0: no analogue input is modelled ``[INF]``.

There are :data:`CHANNELS` channels of each (0..255: the MC2xx range with CAN expansion I/O,
``[BK]``); a number outside it is a run-time error. Every output that changes state logs an
``output`` event (``output``, ``value``) at that instant; writing the state it already has
logs nothing.
"""

from __future__ import annotations

from ...events import EventLog
from .basic_errors import BasicError

CHANNELS = 256
#: ``OP(pattern)``: the first output the pattern's bit 0 drives, and how many it drives.
PATTERN_FIRST = 8
PATTERN_WIDTH = 16


class IoImage:
    """Inputs and outputs of one controller (all OFF at power-up)."""

    def __init__(self, log: EventLog) -> None:
        self.log = log
        self.outputs = [0] * CHANNELS
        self.inputs = [0] * CHANNELS
        self.inverted = [0] * CHANNELS  # INVERT_IN(n, ON): input n reads inverted

    @staticmethod
    def channel(n: float, what: str) -> int:
        """The channel number ``n`` (truncated); BasicError when out of range."""
        i = int(n)
        if not 0 <= i < CHANNELS:
            raise BasicError(f"Parameter out of range: {what}({n:g})")
        return i

    def op(self, n: float, value: float) -> None:
        """OP(n, v): output n ON when v is non-zero, else OFF."""
        self._set(self.channel(n, "OP"), 1 if value else 0)

    def op_pattern(self, pattern: float) -> None:
        """OP(pattern): outputs PATTERN_FIRST.. take the pattern's low bits."""
        bits = int(pattern)
        for k in range(PATTERN_WIDTH):
            self._set(PATTERN_FIRST + k, (bits >> k) & 1)

    def _set(self, i: int, v: int) -> None:
        if self.outputs[i] != v:
            self.outputs[i] = v
            self.log.emit("output", output=i, value=v)

    def read_op(self, n: float) -> float:
        return float(self.outputs[self.channel(n, "READ_OP")])

    def read_in(self, first: float, last: float | None = None) -> float:
        """IN(n), or IN(a, b) as a binary number (bit 0 = input a)."""
        a = self.channel(first, "IN")
        if last is None:
            return float(self.input(a))
        b = self.channel(last, "IN")
        lo, hi = min(a, b), max(a, b)
        return float(sum(self.input(i) << (i - lo) for i in range(lo, hi + 1)))

    def input(self, i: int) -> int:
        """Input ``i`` as the program sees it (1 / 0), INVERT_IN applied."""
        return self.inputs[i] ^ self.inverted[i]

    def invert(self, i: int, on: bool) -> None:
        """INVERT_IN(i, ON / OFF)."""
        self.inverted[i] = 1 if on else 0

    def ain(self, n: float) -> float:
        self.channel(n, "AIN")
        return 0.0

    def set_input(self, n: int, value: float) -> None:
        """An input driven from outside (REST): ON when ``value`` is non-zero."""
        self.inputs[n] = 1 if value else 0


__all__ = ["CHANNELS", "IoImage"]
