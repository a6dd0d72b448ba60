"""System parameters: one value per controller, read (and WDOG written) by any process.

Names from spec §10.11 "system:" and §9.9 (M224-291, M216-274, MCTPL):

* ``WDOG`` — the watchdog relay that enables the drives: 0 (OFF) at power-up, ``WDOG=ON``
  closes it (reads 1). The simulated axes move whatever WDOG is (no drive model) ``[INF]``;
  every change logs a ``wdog`` event (``on``);
* ``VERSION``, ``CONTROL``, ``FREE`` — per model (:mod:`motionsim.sim.trio.card.models`);
* ``SERIAL_NUMBER`` — 0: a simulated board has none ``[INF]``;
* ``SYSTEM_ERROR`` — 0: no system error is modelled ``[INF]``;
* ``MOTION_ERROR``, ``ERROR_AXIS`` — a motion error is raised when an axis' AXISSTATUS, at the
  instant an error condition arises (a following error beyond FE_LIMIT, a software limit hit),
  has a bit set that its ERRORMASK also has (power-up 268: bits 2, 3 and 8, so the following
  error is one and the software limits are not): MOTION_ERROR gets bit n for axis n ``[BK]``,
  ERROR_AXIS the first axis in error (-1 while none), the watchdog relay opens (WDOG reads 0,
  a ``wdog`` event) and a ``motion_error`` event (``axis``, ``axisstatus``) is logged.
  ``DATUM(0)`` clears the motion error and the axes' latched error bits (an MC4 template
  issues it after ``MOTION_ERROR<>0``, spec §10.4); WDOG stays off until written ON ``[INF]``;
* ``SERVO_PERIOD`` — in microseconds, from the config;
* ``LIMIT_BUFFERED`` — how many moves the look-ahead of each axis holds, NTYPE included
  (TJ2H-57): a move waits in its process buffer while the look-ahead of one of its axes is
  full (:mod:`motionsim.sim.trio.motion.buffers`). 64 on ``mc4xx`` / ``mc6xx`` (up to 64
  buffers per axis, TJ2P-20; power-up ``[BK]``), 1..64 writable there; 1 and fixed on the
  MC2xx generation.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .basic_errors import BasicError
from .setup_commands import Comms

if TYPE_CHECKING:
    from ..controller import TrioController

#: LIMIT_BUFFERED per model: (power-up, largest). MC4xx: up to 64 motion buffers per axis
#: (TJ2P-20), the look-ahead size LIMIT_BUFFERED (TJ2H-57), power-up 64 ``[BK]``; the MC2xx
#: generation has NTYPE only (TN20, M206-320): 1, not changeable ``[INF]``.
LIMIT_BUFFERED: dict[bool, tuple[int, int]] = {False: (1, 1), True: (64, 64)}  # by Model.mc4

#: Values fixed by this model of the controller (see the module docstring).
_FIXED = {"SERIAL_NUMBER": 0.0, "SYSTEM_ERROR": 0.0}


class SystemParams:
    """The system parameters of one controller."""

    def __init__(self, ctrl: TrioController) -> None:
        self.ctrl = ctrl
        self.wdog = 0
        self.comms = Comms(ctrl.ethercat_slaves)  # what SETCOM / ETHERNET wrote, the EtherCAT bus
        self.limit_buffered = LIMIT_BUFFERED[ctrl.model.mc4][0]
        ctrl.buffers.depth = self.limit_buffered
        self.motion_error = 0  # bit n: axis n has a motion error
        self.error_axis = -1

    def read(self, name: str) -> float:
        m = self.ctrl.model
        if name == "WDOG":
            return float(self.wdog)
        if name == "VERSION":
            return m.version
        if name == "CONTROL":
            return float(m.control)
        if name == "FREE":
            return m.free
        if name == "SERVO_PERIOD":
            return self.ctrl.clock.period_s * 1e6
        if name == "LIMIT_BUFFERED":
            return float(self.limit_buffered)
        if name == "MOTION_ERROR":
            return float(self.motion_error)
        if name == "ERROR_AXIS":
            return float(self.error_axis)
        if name == "SCOPE_POS":  # the SCOPE's next TABLE entry (sim.trio.run.scope)
            return float(self.ctrl.scope.pos)
        return _FIXED[name]

    def write(self, name: str, value: float) -> None:
        """A program writes a system parameter (WDOG, LIMIT_BUFFERED)."""
        if name == "WDOG":
            self.set_wdog(value)
            return
        top = LIMIT_BUFFERED[self.ctrl.model.mc4][1]
        n = int(value)
        if n != value or not 1 <= n <= top:
            raise BasicError(f"Parameter out of range: LIMIT_BUFFERED={value:g} (1..{top})")
        self.limit_buffered = n
        self.ctrl.buffers.depth = n

    def axis_error(self, axis: int, status: int, mask: int) -> bool:
        """An error condition arose on ``axis`` with AXISSTATUS ``status``: a motion error when
        it meets the axis' ERRORMASK ``mask`` (the module docstring); True if it did."""
        if not status & mask:
            return False
        if not self.motion_error & (1 << axis):
            if self.motion_error == 0:
                self.error_axis = axis
            self.motion_error |= 1 << axis
            self.ctrl.log.emit("motion_error", axis=axis, axisstatus=status)
        self.set_wdog(0)
        return True

    def clear_motion_error(self) -> None:
        """DATUM(0): no axis in error any more; the latched AXISSTATUS error bits clear."""
        self.motion_error = 0
        self.error_axis = -1
        for ax in self.ctrl.axes:
            ax.error_bits = 0

    def set_wdog(self, value: float) -> None:
        on = 1 if value else 0
        if on != self.wdog:
            self.wdog = on
            self.ctrl.log.emit("wdog", on=bool(on))


__all__ = ["SystemParams"]
