"""Faults inside a simulated card, for testing a host's recovery: the hooks the core consults.

Two faults act on the card itself rather than on the link to it (those live in
:mod:`motionsim.app.faults`):

* **a lost BREQ edge** — the rotary buffer's BREQ line goes high, but the host never sees the
  rising edge: no ``breq`` event and no interrupt (``on_rise`` callbacks wait for the next
  edge). The level itself is right, so a host that reads BREQ or ``PR`` again recovers; one
  that only waits for the next interrupt may wait for good ``[INF]`` (a model of an interrupt
  lost between the card and the host, not of a firmware bug);
* **a stalled card** — for a window of simulated time the background gets no processor time
  (:meth:`motionsim.sim.pmac.tasks.cpu.Processor.stall`): host commands queue unanswered, PLCs 1-31
  do not scan and the watchdog is not reloaded, as when foreground tasks take the whole
  processor (TUM p236-237: the background runs only in the time the servo and RTI tasks
  leave).

Decisions are deterministic: a :class:`Selector` counts the occurrences it sees and draws from
its own ``random.Random(seed)`` only for those it may take, so the same inputs and seed lose
the same edges (the command faults of :mod:`motionsim.app.faults` pick commands the same way).
Every loss is logged as a ``fault`` event.
"""

from __future__ import annotations

import random
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any


@dataclass(slots=True)
class Selector:
    """Which occurrences a fault takes: from the ``nth`` one counted on, each with
    ``probability`` (drawn from its own ``random.Random(seed)``, only for the occurrences it
    may take), at most ``count`` of them (None: no limit)."""

    nth: int = 1
    count: int | None = 1
    probability: float = 1.0
    seed: int = 0
    seen: int = 0
    injected: int = 0
    _rng: random.Random = field(init=False, repr=False)

    def __post_init__(self) -> None:
        self._rng = random.Random(self.seed)

    def take(self) -> bool:
        """Count one occurrence; True when the fault takes it."""
        self.seen += 1
        if self.seen < self.nth or (self.count is not None and self.injected >= self.count):
            return False
        if self.probability < 1.0 and self._rng.random() >= self.probability:
            return False
        self.injected += 1
        return True


@dataclass(slots=True)
class EdgeLoss:
    """Lose rising BREQ edges of coordinate system ``cs`` (any CS if None), as ``select``
    picks them among that CS's edges."""

    fault: str
    cs: int | None
    select: Selector

    def takes(self, cs: int) -> bool:
        """Count this edge; True when it is lost."""
        return (self.cs is None or cs == self.cs) and self.select.take()


class CardFaults:
    """The faults active inside one controller; the core asks :meth:`lose_breq_rise` at every
    rising BREQ edge (only when a loss is set: :attr:`active`)."""

    __slots__ = ("active", "_emit", "_losses")

    def __init__(self, emit: Callable[..., Any]) -> None:
        self._emit = emit
        self._losses: list[EdgeLoss] = []
        #: True while any edge loss is set (the rotary buffer's fast check).
        self.active = False

    def add_edge_loss(self, loss: EdgeLoss) -> None:
        self._losses.append(loss)
        self.active = True

    def remove(self, fault: str) -> None:
        """Forget the losses of fault ``fault``."""
        self._losses = [x for x in self._losses if x.fault != fault]
        self.active = bool(self._losses)

    def lose_breq_rise(self, cs: int) -> bool:
        """A rising BREQ edge of ``cs`` is about to be signalled: True if it is lost (then a
        ``fault`` event says so, at the same instant)."""
        for loss in self._losses:
            if loss.takes(cs):
                self._emit("fault", fault=loss.fault, kind="breq_lost", cs=cs)
                return True
        return False


__all__ = ["CardFaults", "EdgeLoss", "Selector"]
