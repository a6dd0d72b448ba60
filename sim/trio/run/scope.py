"""Trio ``SCOPE`` and ``TRIGGER``: parameters sampled into TABLE every few servo periods.

The Trio help page of SCOPE (Trio MC4 help, "SCOPE", auto-converted copy in the code corpus):

* ``SCOPE(ON, period, table_start, table_stop, p0[, p1 ... p7])`` arms the capture of up to
  eight parameters every ``period`` servo periods into the TABLE range; ``SCOPE(ON, period)``
  changes the period on the fly; ``SCOPE(OFF)`` disarms it, so TRIGGER starts nothing.
* The parameters share the range: with two of them in ``0 .. 1000`` the first goes to
  TABLE(0)..TABLE(499), the second to TABLE(500)..TABLE(999) (the page's example 1). So each
  parameter gets ``(table_stop - table_start) // n`` entries, table_stop itself unused.
* Once armed, TRIGGER starts the capture, which runs until the range is filled; "TRIGGER may
  specify one-shot or automatic": ``TRIGGER`` (or ``TRIGGER(0)``) is one shot, ``TRIGGER(1)``
  automatic — the capture goes round the range again from the start until ``SCOPE(OFF)``
  ``[INF]`` (the TRIGGER page itself was not found).

``[INF]`` where the page is silent: the first sample is taken on the servo period after
TRIGGER, then one every ``period`` servo periods; the parameters are read as the process that
ran ``SCOPE(ON, ...)`` reads them (its BASE axis for a parameter without ``AXIS(n)``), and are
read once when SCOPE runs so that a bad one is that statement's run-time error; a one-shot
capture that has filled its range leaves the scope armed for the next TRIGGER; a parameter
that fails while sampling (its axis gone after a reset) ends the capture. ``SCOPE_POS`` reads
:attr:`Scope.pos`. The FIFO form (``SCOPE(ON, period, "name", ...)``) and ``SCOPE_DELAY`` are
not simulated.

Each change is a ``scope`` event (``state``: ``armed``, ``triggered``, ``done``, ``off``).
Nothing runs while no capture does; a capture costs one wake-up per sample.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Final

from ...recording import Recording
from ...simpy_adapter import Wake, cancel, wake_at
from ..card.basic_errors import BasicError

if TYPE_CHECKING:
    from .context import Context

MAX_PARAMS: Final = 8
Reader = Callable[[Any], Any]


@dataclass(frozen=True, slots=True)
class ScopeRecording:
    """What the last capture stored: each parameter's ``names`` and TABLE ``columns``
    (entries in time order) and the servo period of each sample (``cycles``)."""

    names: tuple[str, ...]
    period_cycles: int
    servo_period_s: float
    table_start: int
    cycles: tuple[int, ...]
    columns: tuple[tuple[float, ...], ...]
    running: bool
    cyclic: bool
    armed: bool
    per_param: int
    wrapped: bool

    def shared(self) -> Recording:
        """As :class:`motionsim.sim.recording.Recording` (a capture that went round is
        ``wrapped``)."""
        return Recording(
            "scope", self.names,
            tuple({"name": n, "table_start": self.table_start + i * self.per_param}
                  for i, n in enumerate(self.names)),
            self.cycles, self.columns, self.period_cycles, self.servo_period_s, self.running,
            self.wrapped, self.per_param)


def _range_error(what: str) -> BasicError:
    return BasicError(f"Parameter out of range: SCOPE {what}")


class Scope:
    """The controller's one software scope (``ctrl``: the TrioController)."""

    def __init__(self, ctrl: Any) -> None:
        self._ctrl = ctrl
        self.armed = False
        self.running = False
        self.cyclic = False
        self.period = 1
        self.start = 0
        self.per_param = 0
        self.names: tuple[str, ...] = ()
        self._readers: tuple[Reader, ...] = ()
        self._ctx: Context | None = None
        self._slots: list[int] = []  # servo period of each sample slot
        self._stored = 0
        self._next_k = 0
        self._wake: Wake | None = None

    # -- SCOPE ------------------------------------------------------------------------------

    def set(self, ctx: Context, enable: float, period: float | None,
            table: tuple[float, float] | None, readers: Sequence[Reader],
            names: Sequence[str]) -> None:
        """``SCOPE(enable[, period[, start, stop, p0 ...]])`` (module docstring).

        Raises:
            BasicError: a period below 1, a TABLE range outside TABLE or too small for one
                sample of each parameter, more than 8 parameters, or a parameter that cannot
                be read.
        """
        if not enable:
            self.off()
            return
        if period is None:
            raise _range_error("ON needs a period")
        if period != int(period) or period < 1:
            raise _range_error(f"period {period:g} (servo periods, 1 or more)")
        if table is None:
            if not self.armed:
                raise BasicError("SCOPE(ON, period) needs the TABLE range and parameters "
                                 "the first time")
            self.period = int(period)  # on the fly (the page's example 3)
            self._log_state("armed")
            return
        start, stop = table
        size = self._ctrl.table_size
        if start != int(start) or stop != int(stop) or not 0 <= start < stop <= size:
            raise _range_error(f"TABLE range {start:g}..{stop:g} (0..{size})")
        n = len(readers)
        if not 1 <= n <= MAX_PARAMS:
            raise _range_error(f"takes 1 to {MAX_PARAMS} parameters, got {n}")
        per_param = int(stop - start) // n
        if per_param < 1:
            raise _range_error(f"TABLE range {start:g}..{stop:g} holds no sample of {n} "
                               "parameters")
        for read in readers:
            float(read(ctx))  # a parameter that cannot be read fails here, at SCOPE
        self.end()
        self.period, self.start, self.per_param = int(period), int(start), per_param
        self._readers, self.names, self._ctx = tuple(readers), tuple(names), ctx
        self.armed = True
        self._slots, self._stored = [], 0
        self._log_state("armed")

    def off(self) -> None:
        """``SCOPE(OFF)``: disarm; a capture in progress stops where it is."""
        was = self.armed
        self.end()
        self.armed = False
        if was:
            self._log_state("off")

    def end(self) -> None:
        cancel(self._wake)
        self.running = False

    def detach(self) -> None:
        """Power-down: nothing more is sampled."""
        self.end()
        self.armed = False

    # -- TRIGGER ----------------------------------------------------------------------------

    def trigger(self, mode: float) -> None:
        """``TRIGGER[(mode)]``: 0 one shot, 1 automatic; nothing while SCOPE is off."""
        if mode not in (0, 1):
            raise BasicError(f"Parameter out of range: TRIGGER({mode:g}) (0 one shot, "
                             "1 automatic)")
        if not self.armed:
            return
        self.end()
        self.cyclic = mode == 1
        self.running = True
        self._slots, self._stored = [], 0
        clock = self._ctrl.clock
        self._next_k = clock.after(self._ctrl.env.now)
        self._log_state("triggered")
        self._wake = wake_at(self._ctrl.env, clock.t(self._next_k), self._sample, self._wake)

    def _sample(self, _event: Any) -> None:
        if not self.running or self._ctx is None:
            return
        ctx, ctrl = self._ctx, self._ctrl
        j = self._stored % self.per_param
        try:
            values = [float(read(ctx)) for read in self._readers]
        except BasicError as exc:
            self.running = False
            self._log_state("done", error=str(exc))
            return
        table = ctrl.table
        for i, v in enumerate(values):
            table[self.start + i * self.per_param + j] = v
        k = self._next_k
        if j < len(self._slots):
            self._slots[j] = k
        else:
            self._slots.append(k)
        self._stored += 1
        if self._stored >= self.per_param and not self.cyclic:
            self.running = False
            self._log_state("done")
            return
        self._next_k = k + self.period
        self._wake = wake_at(ctrl.env, ctrl.clock.t(self._next_k), self._sample, self._wake)

    # -- reading ----------------------------------------------------------------------------

    @property
    def pos(self) -> int:
        """SCOPE_POS: the TABLE entry the first parameter's next sample goes to ``[BK]``; a
        one-shot capture that filled its range: one past its last entry ``[INF]``."""
        if not self.per_param:
            return self.start
        if self.cyclic:
            return self.start + self._stored % self.per_param
        return self.start + min(self._stored, self.per_param)

    def recording(self) -> ScopeRecording:
        """The samples now in TABLE, oldest first (a capture that went round: the newest
        ``per_param`` of them)."""
        order = list(range(len(self._slots)))
        if self._stored > self.per_param:
            head = self._stored % self.per_param
            order = order[head:] + order[:head]
        table = self._ctrl.table
        columns = tuple(
            tuple(table.get(self.start + i * self.per_param + j, 0.0) for j in order)
            for i in range(len(self.names))
        )
        return ScopeRecording(self.names, self.period, self._ctrl.clock.period_s, self.start,
                              tuple(self._slots[j] for j in order), columns, self.running,
                              self.cyclic, self.armed, self.per_param,
                              self._stored > self.per_param)

    def _log_state(self, state: str, **extra: Any) -> None:
        self._ctrl.log.emit("scope", state=state, period=self.period, samples=min(
            self._stored, self.per_param), **extra)


__all__ = ["MAX_PARAMS", "Scope", "ScopeRecording"]
