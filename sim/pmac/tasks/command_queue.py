"""The card's bounded queue of program-issued commands (``CMD"..."``, TSRM p422-424).

A PLC's ``CMD"text"`` does not run the command: it is placed in the command queue, which the
background command interpreter works through one command per background cycle, between its
other tasks. The queue is finite: "If there is no room for a new command, program execution is
temporarily halted until the new command can be placed on the queue" (TSRM p423). So a PLC that
issues commands faster than the interpreter takes them does not grow the card's memory: it
stops at the command that does not fit and goes on when there is room.

Modelled here:

* at most :data:`CAPACITY` program-issued commands wait in the queue at once ``[INF]`` (the
  manual gives no figure);
* a scan's commands are placed at its end (they are not interpreted before the end of the scan,
  TSRM p423); those that do not fit wait with their PLC, which is **halted**: it is not scanned
  again until every one of its waiting commands is in the queue ``[INF]`` (the statements after
  the ``CMD`` of that one scan already ran: the card halts at the ``CMD`` itself);
* room made by the interpreter is given to the waiting PLCs lowest number first, each PLC's
  commands in the order issued;
* ``DISABLE PLC n`` (from a host, or another PLC), ``<CTRL-D>`` and a reset end PLC n's queued
  and waiting commands: they are never interpreted ``[INF]``. A PLC's own ``DISABLE`` ends its
  scan but keeps what it issued (the init-PLC idiom ``CMD"..."`` ... ``DISABLE PLC1``).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Iterable
from typing import Final

#: Program-issued commands the queue holds at once ``[INF]``.
CAPACITY: Final = 32

#: A PLC: ``(compiled, number)``.
Source = tuple[bool, int]
#: One command: ``(text, cs, motor)`` (the PLC's addressing when it was issued).
Command = tuple[str, int, int]
#: Puts one command in the card's background queue; the callable given runs when the
#: interpreter takes it and says whether it is still to be interpreted.
Place = Callable[[Command, Callable[[], bool]], None]


class CommandQueue:
    """The program side of the card's command queue: how many commands wait in it, and what
    each halted PLC still has to place. ``place`` queues one command for the interpreter."""

    def __init__(self, place: Place) -> None:
        self._place = place
        self.queued = 0
        #: Commands of each PLC not yet in the queue (its PLC is halted while any are).
        self._waiting: dict[Source, deque[Command]] = {}
        #: Bumped when a PLC's work is ended: its queued commands of older generations are
        #: dropped when the interpreter reaches them.
        self._generation: dict[Source, int] = {}
        #: Commands dropped by DISABLE / reset (for reports and tests).
        self.ended = 0

    def halted(self, source: Source) -> bool:
        """Whether ``source`` waits for room in the queue (it is not scanned meanwhile)."""
        return bool(self._waiting.get(source))

    def waiting(self) -> int:
        """Commands issued and not yet in the queue, over every PLC."""
        return sum(len(q) for q in self._waiting.values())

    def issue(self, source: Source, commands: Iterable[Command]) -> None:
        """The commands one scan of ``source`` issued, in order: queued as room allows."""
        q = self._waiting.setdefault(source, deque())
        q.extend(commands)
        self._fill()

    def end(self, source: Source) -> None:
        """``DISABLE PLC``: ``source``'s waiting commands are dropped, and its queued ones will
        not be interpreted."""
        q = self._waiting.pop(source, None)
        if q:
            self.ended += len(q)
        self._generation[source] = self._generation.get(source, 0) + 1

    def _fill(self) -> None:
        while self.queued < CAPACITY:
            ready = [s for s, q in self._waiting.items() if q]
            if not ready:
                return
            source = min(ready)
            command = self._waiting[source].popleft()
            self.queued += 1
            self._place(command, self._taker(source))

    def _taker(self, source: Source) -> Callable[[], bool]:
        generation = self._generation.get(source, 0)

        def taken() -> bool:
            self.queued -= 1
            live = self._generation.get(source, 0) == generation
            if not live:
                self.ended += 1
            self._fill()
            return live

        return taken


__all__ = ["CAPACITY", "CommandQueue"]
