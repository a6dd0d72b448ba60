"""The motor status reply ``#n?``: two 24-bit words, 12 hex digits (TSRM p281-284; spec §11.9).

Characters 1-6 are word 1 (X:$0000B0 for motor 1), 7-12 word 2 (Y:$0000C0). The manual's
example ``81200001C401`` reads: activated, integration mode, desired velocity zero | CS 1,
A-axis, assigned to a CS, (bit 14), home complete, in position.

Bits driven here (others stay 0; there are no limit switches, amplifier faults, phasing or
following errors in the simulation ``[INF]``):

The manual's example has word 1 bit 19 clear although its motor is enabled; the EPICS driver and
dls-pmac-control both read bit 19 as "amplifier enabled", so it is set here ``[INF]``.

word 1: 23 motor activated (always ``[INF]``: Ixx00 is not consulted), 22 / 21 negative /
positive end limit set (beyond the software limit Ixx14 / Ixx13), 19 amplifier enabled
(not killed), 18 open-loop mode (killed or ``O``), 17 move timer active (a definite jog, the
post-trigger home move, or a program move of its CS ``[INF]``), 16 integration mode
(Ixx34 = 1), 15 dwell in progress (its CS), 14 data block error (its CS aborted on a
run-time error), 13 desired velocity zero, 12 abort deceleration (CTRL-A of a jog),
10 home search or trigger search in progress.

word 2: 23-20 CS number − 1, 19-16 axis definition code (1 A, 2 B, 3 C, 4 U/V/W, 7 X/Y/Z —
the codes dls-pmac-control's ``status.py`` decodes), 15 assigned to a CS, 14 set with
amplifier enabled (reproduces the manual's example; the bit is reserved on Turbo ``[INF]``),
11 stopped on position limit, 10 home complete, 7 trigger move (a jog-until-trigger
started and found no trigger yet), 0 in position (loop closed, desired velocity
zero, no move timer).
"""

from __future__ import annotations

from typing import Any

from ..buffers.motion import DWELL
from ..card.variables import Variables, ixx
from .motors import CLOSED, KILLED, Motor

#: Axis definition code in word 2 bits 19-16, by axis letter.
AXIS_CODE = {"A": 1, "B": 2, "C": 3, "U": 4, "V": 4, "W": 4, "X": 7, "Y": 7, "Z": 7}


def motor_status_words(
    motor: Motor, axis: tuple[int, str, float] | None, cs: Any, vars_: Variables, t: float
) -> tuple[int, int]:
    """The two words of ``#n?`` for ``motor`` at ``t``.

    Args:
        motor: the motor.
        axis: its axis definition ``(cs, letter, scale)`` or None.
        cs: the :class:`motionsim.sim.pmac.lookahead.CoordSystem` it belongs to, or None.
        vars_: the variable store (Ixx34).
        t: now.
    """
    w1 = 1 << 23
    w2 = 0
    amp = motor.loop != KILLED
    if amp:
        w1 |= 1 << 19
        w2 |= 1 << 14
    if motor.loop != CLOSED:
        w1 |= 1 << 18
    if vars_.I(ixx(motor.n, 34)) == 1:
        w1 |= 1 << 16
    cs_moving = cs is not None and cs.moving
    timer = motor.definite or cs_moving
    if timer:
        w1 |= 1 << 17
    if cs is not None:
        cur = cs.current
        if cur is not None and cur.kind == DWELL:
            w1 |= 1 << 15
        if cs.run_time_error:
            w1 |= 1 << 14
    dvz = not motor.moving(t) and not cs_moving
    if dvz:
        w1 |= 1 << 13
    if motor.aborting:
        w1 |= 1 << 12
    if motor.homing or motor.trigger_search:
        w1 |= 1 << 10
    hi, lo = motor.soft_limits()
    p = motor.position(t)
    if hi is not None and p > hi:
        w1 |= 1 << 21
    if lo is not None and p < lo:
        w1 |= 1 << 22
    if motor.limit_stop:
        w2 |= 1 << 11
    if axis is not None:
        w2 |= ((axis[0] - 1) & 0xF) << 20
        w2 |= AXIS_CODE.get(axis[1], 0) << 16
        w2 |= 1 << 15
    if motor.home_complete:
        w2 |= 1 << 10
    if motor.trigger_move:
        w2 |= 1 << 7
    if motor.loop == CLOSED and dvz and not timer and motor.command is None:
        w2 |= 1
    return w1, w2


__all__ = ["AXIS_CODE", "motor_status_words"]
