"""Fixed motion programs: ``OPEN PROG n`` / ``CLEAR`` / ``CLOSE``, ``&c B n R`` (TSRM p381,
p295; spec §11.8).

A fixed program is a numbered buffer of program lines (1..32767) held in the card's buffer
memory. Entry: ``OPEN PROG n`` on one port (ERR007 if any buffer is open, ERR001 while any
coordinate system runs a program), lines are compiled and stored as the rotary buffer's are
(same parser, same word count), ``CLEAR`` empties it, ``CLOSE`` ends entry. While a PROG is
open no CS may run (ERR015), and after any PROG was opened every CS must be pointed again
with ``B{n}`` before ``R`` / ``S`` (ERR015 otherwise).

Running: ``B{n}`` points a CS at program n; ``R`` runs it through the same move planning and
execution as the rotary program (:mod:`motionsim.sim.pmac.lookahead`), which reads its lines
through :class:`ProgramRun` — the interface a
:class:`motionsim.sim.pmac.buffers.rotary.RotaryBuffer`
offers it. The difference: a fixed program **ends** at its end (the listing's implicit
``RET``): the CS is ``stopped`` once the last calculated move is done, where a rotary program
would wait for more lines. ``[INF]`` a later ``R`` without a new ``B`` runs it again from the
top; program lines keep their memory while they run (nothing is freed).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable
from typing import Any

from motionsim.sim.controller import Port
from motionsim.sim.errors import Conflict, NotFound
from motionsim.sim.pmac.buffers.program import ProgramLine

N_PROGRAMS = 32767


class ProgramRun:
    """Program ``number`` as coordinate system ``cs``'s line source (the rotary buffer's
    interface: ``pending``, ``take``, ``take_simple``, ``line_calculated``, ``n_loaded``,
    ``calculated``, ``free_calculated``), numbered from 1."""

    ends = True  # the program stops at its end (a rotary buffer waits)
    full = False

    def __init__(
        self, cs: int, number: int, lines: list[ProgramLine], emit: Callable[..., Any]
    ) -> None:
        self.cs = cs
        self.number = number
        self.pending: deque[tuple[int, ProgramLine]] = deque(
            (i, line) for i, line in enumerate(lines, start=1)
        )
        self.n_loaded = len(lines)
        self.calculated: deque[tuple[int, int]] = deque()  # always empty: nothing is freed
        self._emit = emit

    def take(self) -> tuple[int, ProgramLine] | None:
        return self.pending.popleft() if self.pending else None

    def take_simple(self) -> int:
        n, _line = self.pending.popleft()
        self.line_calculated(n)
        return n

    def line_calculated(self, n: int) -> None:
        self._emit("line_calculated", cs=self.cs, n=n, prog=self.number)

    def free_calculated(self) -> None:
        """Program lines stay in memory."""


class MotionPrograms:
    """The fixed motion programs of one controller and the one that may be open for entry."""

    def __init__(self) -> None:
        self.programs: dict[int, list[ProgramLine]] = {}
        self._edit: tuple[Port, int] | None = None

    def editing(self, port: Port | None = None) -> int | None:
        """The program open for entry (on ``port`` if given), or None."""
        e = self._edit
        if e is None or (port is not None and e[0] is not port):
            return None
        return e[1]

    def open(self, n: int, port: Port) -> None:
        """``OPEN PROG n`` (the controller has checked the ERR007 / ERR001 rules)."""
        if not 1 <= n <= N_PROGRAMS:
            raise NotFound(f"no PROG {n} (1..{N_PROGRAMS})")
        self.programs.setdefault(n, [])
        self._edit = (port, n)

    def store(self, line: ProgramLine) -> None:
        """One compiled line at the end of the open program."""
        assert self._edit is not None
        self.programs[self._edit[1]].append(line)

    def clear(self) -> None:
        """``CLEAR``: empty the open program."""
        assert self._edit is not None
        self.programs[self._edit[1]] = []

    def close(self, port: Port) -> None:
        """``CLOSE`` on ``port``."""
        if self._edit is not None and self._edit[0] is port:
            self._edit = None

    def words(self) -> int:
        """Buffer memory the programs take."""
        return sum(line.words for lines in self.programs.values() for line in lines)

    def run_of(self, cs: int, n: int, emit: Callable[..., Any]) -> ProgramRun:
        """A fresh run of program ``n`` for ``cs`` (ERR015 if it does not exist or is open)."""
        lines = self.programs.get(n)
        if lines is None or not lines:
            raise Conflict(f"there is no PROG {n}", pmac_error="ERR015")
        if self.editing() == n:
            raise Conflict(f"PROG {n} is open: CLOSE it first", pmac_error="ERR015")
        return ProgramRun(cs, n, lines, emit)


__all__ = ["N_PROGRAMS", "MotionPrograms", "ProgramRun"]
