"""DATUM(1..6): the homing sequences, run against the simulated datum input and Z mark.

TJ2P5-247 (spec §11.6, §10.4) names the sequences; the phases and speeds are ``[BK]`` (the
TRM page, and TJ2 §3.2.72, were not reachable):

====== ======================================================================================
mode    sequence
====== ======================================================================================
1 / 2   forward / reverse at CREEP to the encoder's Z mark; the datum is there
3 / 4   forward / reverse at SPEED until the datum input (DATUM_IN) is active, decelerate at
        DECEL, then back at CREEP until the input is no longer active; the datum is there
5 / 6   as 3 / 4, then on at CREEP, in the same direction, to the next Z mark: the datum
====== ======================================================================================

At the datum the axis' position is redefined as 0 (TRM p. 8-30: "DATUM sequences always set
a datum of zero"; DEFPOS is used after them) and the axis decelerates to rest at DECEL, so it
ends within a stopping distance of 0, on a whole edge (``[BK]``). A sequence that starts with
the datum input already active skips the fast search and goes straight to the creep phase
``[BK]``. The input is sampled once per servo period (inputs are read at the start of each
servo cycle, TJ1P-31), so the datum lies where the axis was in the period the input changed.

* The datum input is **active low** ``[BK]``, like the limit inputs: it is active while
  ``IN(DATUM_IN)`` reads OFF — write ``PUT .../variables/IN(n)`` 1 to clear the switch, 0 to
  reach it; ``INVERT_IN(n, ON)`` turns it into an active-high input. Usage agrees (spec §2.5,
  MPT): a real MC4 project homes with ``DATUM_IN = in_rotate_home`` and ``DATUM(4)``, and its
  own simulator program drives that input OFF while the axis is inside the home sensor's
  window and ON everywhere else.
* The Z mark ``[INF]``: no encoder is simulated; one Z mark per revolution is modelled as one
  every user unit of DPOS (set UNITS to the edges per revolution), reached when the position
  crosses a whole number of units.
* MTYPE reads 12 and AXISSTATUS bit 6 is set while a sequence runs; CANCEL decelerates it to
  rest at DECEL and ends it without a datum. Each datum found logs a ``datum`` event
  (``axis``, ``mode``, ``at`` = the position, before the reset, where it was found).
* DATUM(3..6) with DATUM_IN = -1 (no input) is a run-time error, as is a mode outside 0..6.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ..card.basic_errors import BasicError
from .moves import Move
from .profile import Profile, endless

if TYPE_CHECKING:
    from ...events import EventLog
    from ..card.io import IoImage
    from ..controller import TrioController
    from .axis import Axis

_HOLD = Profile([(0.0, 0.0, 0.0, 0.0, 0.0)], math.inf, math.inf)
_EPS = 1e-9

#: Modes: (search direction, uses the datum input, then seeks a Z mark).
MODES: dict[int, tuple[int, bool, bool]] = {
    1: (1, False, True), 2: (-1, False, True), 3: (1, True, False), 4: (-1, True, False),
    5: (1, True, True), 6: (-1, True, True),
}


def check_datum(mode: float, datum_in: float) -> None:
    """Run-time checks of ``DATUM(mode)`` (a BasicError stops the process)."""
    if mode != int(mode) or not 0 <= mode <= 6:
        raise BasicError(f"Parameter out of range: DATUM({mode:g}) (modes 0..6)")
    if MODES.get(int(mode), (0, False, False))[1] and datum_in < 0:
        raise BasicError(f"DATUM({int(mode)}) needs a datum input: DATUM_IN is {datum_in:g}")


class DatumMove(Move):
    """A DATUM(n) sequence on one axis, advanced once per servo period (:meth:`tick`)."""

    __slots__ = ("io", "log", "axis", "phase", "then", "x_o", "t_o", "dir", "prof", "prev",
                 "datum_in", "done")

    def bind(self, io: IoImage, log: EventLog) -> None:
        self.io = io
        self.log = log

    # -- the phases ------------------------------------------------------------------------

    def begin(self, tick: int, t_start: float, axes: list[Axis], v0: float = 0.0) -> None:
        ax = self.axis = axes[0]
        self.p0 = (ax.own_position(),)
        self.start_tick, self.t_start = tick, t_start
        self.unit = (1.0,)
        self.end_pos = self.p0
        self.profile = _HOLD
        self.done = False
        self.then = ""
        self.datum_in = int(ax.stored.values["DATUM_IN"])
        self.x_o, self.t_o, self.prev = self.p0[0], t_start, self.p0[0]
        seek, uses_input, _z = MODES[int(self.args[0])]
        if not uses_input:
            self._run("ZSEEK", seek, ax.creep, t_start)
        elif self._active():
            self._run("CREEP", -seek, ax.creep, t_start)
        else:
            self._run("SEEK", seek, ax.speed, t_start)

    def _active(self) -> bool:
        return self.io.input(self.datum_in) == 0

    def _run(self, phase: str, direction: int, speed: float, t: float) -> None:
        self.x_o, self.t_o = self._pos(t) if self.phase_set() else self.x_o, t
        self.phase, self.dir = phase, direction
        self.prof = endless(speed, self.axis.accel)

    def phase_set(self) -> bool:
        return hasattr(self, "prof")

    def _stop(self, t: float, then: str) -> None:
        """Decelerate to rest at DECEL from where the axis is, then go on with ``then``."""
        self.prof = self.prof.cancelled_at(t - self.t_o, self.axis.decel)
        self.phase, self.then = "STOPPING", then

    def _pos(self, t: float) -> float:
        return self.x_o + self.dir * self.prof.s(t - self.t_o)

    def _datum(self, t: float, here: float) -> None:
        """The datum is found at ``here``: that position becomes 0."""
        self.x_o -= here
        self.prev -= here
        self.log.emit("datum", axis=self.axis.n, mode=int(self.args[0]), at=here)

    def tick(self, t: float) -> str | None:
        """One servo period at instant ``t``: sample the input, move on a phase; ``"end"``
        when the sequence is over."""
        here = self._pos(t)
        phase = self.phase
        seek, _uses_input, z_mark = MODES[int(self.args[0])]
        if phase == "SEEK":
            if self._active():
                self._stop(t, "CREEP")
        elif phase == "STOPPING":
            if t - self.t_o >= self.prof.duration - _EPS:
                if self.then == "END":
                    self.end_pos = (here,)
                    return "end"
                self._run("CREEP", -seek, self.axis.creep, t)
        elif phase == "CREEP":
            if not self._active():
                if z_mark:
                    self.phase = "ZSEEK"
                else:
                    self._datum(t, here)
                    self._stop(t, "END")
        elif phase == "ZSEEK" and (
                math.floor(here + _EPS) > math.floor(self.prev + _EPS) if self.dir > 0
                else math.ceil(here - _EPS) < math.ceil(self.prev - _EPS)):
            self._datum(t, here)
            self._stop(t, "END")
        self.prev = self._pos(t)
        return None

    # -- as a move in MTYPE ------------------------------------------------------------------

    def positions(self, tau: float) -> tuple[float, ...]:
        if self.done:
            return self.end_pos
        return (self._pos(self.t_start + tau),)

    def speed(self, tau: float) -> float:
        if self.done:
            return 0.0
        return self.prof.v(self.t_start + tau - self.t_o)

    def finish_at(self, tau: float) -> None:
        self.done = True
        self.profile = Profile([(0.0, 0.0, 0.0, 0.0, 0.0)], tau, 0.0)

    def cancel_at(self, tau: float, decel: float, sramp_s: float = 0.0) -> None:
        """CANCEL: decelerate to rest and end, no datum."""
        self.cancelled = True
        if self.phase != "STOPPING":
            self._stop(self.t_start + tau, "END")
        else:
            self.then = "END"

    def shift(self, i: int, offset: float) -> None:
        self.x_o += offset
        self.prev += offset

    def needs_tick(self) -> bool:
        return True

    def remaining(self, tau: float | None) -> float:
        return 0.0

    def endmove(self, i: int) -> float | None:
        return None

    def follows_speed(self) -> bool:
        return False


def datum_move(ctrl: TrioController, axis: int, args: tuple[float, ...], process: int,
               text: str) -> DatumMove:
    """The DATUM(n) move of ``process`` on ``axis``, checked (BasicError) and bound to the
    controller's inputs and log."""
    check_datum(args[0], ctrl.axes[axis].stored.values["DATUM_IN"])
    move = DatumMove(ctrl.buffers.new_id(), "DATUM", (axis,), args, process, text)
    move.bind(ctrl.io, ctrl.log)
    return move


__all__ = ["MODES", "DatumMove", "check_datum", "datum_move"]
