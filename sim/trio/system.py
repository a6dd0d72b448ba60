"""System parameters: one value per controller, read (and WDOG written) by any process.

Names from spec §10.11 "system:" and §9.9 (M224-291, M216-274, MCTPL):

* ``WDOG`` — the watchdog relay that enables the drives: 0 (OFF) at power-up, ``WDOG=ON``
  closes it (reads 1). The simulated axes move whatever WDOG is (no drive model) ``[INF]``;
  every change logs a ``wdog`` event (``on``);
* ``VERSION``, ``CONTROL``, ``FREE`` — per model (:mod:`motionsim.sim.trio.models`);
* ``SERIAL_NUMBER`` — 0: a simulated board has none ``[INF]``;
* ``SYSTEM_ERROR``, ``MOTION_ERROR`` — 0: no error model (no following error, drive faults
  or enforced limits, :mod:`motionsim.sim.trio.axis_status`) ``[INF]``;
* ``ERROR_AXIS`` — -1 while no axis has a motion error ``[INF]``;
* ``SERVO_PERIOD`` — in microseconds, from the config.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from motionsim.sim.trio.controller import TrioController

#: Values fixed by this model of the controller (see the module docstring).
_FIXED = {"SERIAL_NUMBER": 0.0, "SYSTEM_ERROR": 0.0, "MOTION_ERROR": 0.0, "ERROR_AXIS": -1.0}


class SystemParams:
    """The system parameters of one controller."""

    def __init__(self, ctrl: TrioController) -> None:
        self.ctrl = ctrl
        self.wdog = 0

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
        return _FIXED[name]

    def set_wdog(self, value: float) -> None:
        on = 1 if value else 0
        if on != self.wdog:
            self.wdog = on
            self.ctrl.log.emit("wdog", on=bool(on))


__all__ = ["SystemParams"]
