"""The Servo-IC I-variables of the card's 8 local axes (Servo ICs 0 and 1, I7000-I7199).

The card modelled is a Geo Brick (``CID`` 603382, :mod:`.factory`): its clocks come from Servo
IC 0, and its 8 axes are the 4 channels of Servo ICs 0 and 1. The factory dump the defaults
follow is of a MACRO card with no Servo IC (all of I7000-I7999 are 0 there, spec §11.6), so
these values come from the PMAC2-style clock rules and the dump's MACRO IC 0, which carries
the same variables (I6800 = 6527, I6802 = 3, I6803 = 2258, I6804 = 15, I68n0 = 7, I68n2 = 1):

* the clock chain (TSRM I7m00-I7m02; TSRM p216 for the default servo clock): MaxPhase =
  117.9648 MHz / (2·I7m00 + 3), phase = MaxPhase / (I7m01 + 1), servo = phase / (I7m02 + 1).
  The values are derived from the simulator's servo period (I10, or the ``servo_hz``
  config) so that the chain gives that period: I7m01 = 0 and I7m02 = 3 (four phase cycles
  per servo cycle, the default) unless I7m00 would leave its range 0..32767, then the
  smallest dividers that fit ``[INF]``. The default period (I10 = 3 713 707) gives I7000 =
  6527, the Turbo default, 442.74 µs against the simulator's 442.71 µs (the 0.008 % of
  :mod:`.factory`). Both ICs run the same values (IC 1 takes its clocks from IC 0; its own
  settings only matter if it were the source ``[INF]``);
* I7m03 = 2258 (hardware clocks), I7m04 = 15 (PWM deadtime / PFM pulse width), as the
  MACRO IC's I6803 / I6804 ``[INF]``;
* per channel n = 1..4: I7mn0 = 7 (encoder decode, x4 quadrature), I7mn2 = 1 (capture
  control: on the flag going high), I7mn3 = 0 (capture flag: the home flag) — the MACRO
  IC's channel defaults ``[INF]``. The EPICS driver reads I70n2 / I70n3 (I71n2 / I71n3 for
  axes 5-8) before homing to decide whether limits must be disabled.

Nothing reads these back for simulation: the servo period stays I10's (or ``servo_hz``);
they are reported so that a host computing the CPU load (the EPICS driver divides M72 by
M70·(I7002+1)) or the home flags gets the card's real values.
"""

from __future__ import annotations

from typing import Final

#: The PMAC2-style ICs' clock oscillator (Hz).
OSCILLATOR_HZ: Final = 117_964_800.0
_ICS: Final = (7000, 7100)
_MAX_I7M00: Final = 32767


def clock_dividers(period_s: float) -> tuple[int, int, int]:
    """``(I7m00, I7m01, I7m02)`` whose clock chain gives a servo period of ``period_s``."""
    for phase_div in range(16):
        for servo_div in (3, *range(4, 16), 2, 1, 0):
            # period = (2*I7m00 + 3) * (I7m01 + 1) * (I7m02 + 1) / oscillator
            x = (period_s * OSCILLATOR_HZ / ((phase_div + 1) * (servo_div + 1)) - 3) / 2
            if 0 <= round(x) <= _MAX_I7M00:
                return round(x), phase_div, servo_div
    return _MAX_I7M00, 15, 15  # slower than the ICs can clock: the slowest they run


def ivars(period_s: float) -> dict[int, float]:
    """The Servo-IC I-variables for a servo period of ``period_s`` (module docstring)."""
    i00, i01, i02 = clock_dividers(period_s)
    out: dict[int, float] = {}
    for base in _ICS:
        out.update({base: i00, base + 1: i01, base + 2: i02, base + 3: 2258, base + 4: 15})
        for n in range(1, 5):
            out.update({base + 10 * n: 7, base + 10 * n + 2: 1, base + 10 * n + 3: 0})
    return {n: float(v) for n, v in out.items()}


__all__ = ["OSCILLATOR_HZ", "clock_dividers", "ivars"]
