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

Control flow: :mod:`.flow` (structure, at entry) and :mod:`.program_run` (running).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ...controller import Port
from ...errors import Conflict, NotFound
from .flow import STRUCTURAL, Code, Structure, build
from .program import ProgramLine
from .program_run import ProgramRun

N_PROGRAMS = 32767


class MotionPrograms:
    """The fixed motion programs of one controller and the one that may be open for entry."""

    def __init__(self) -> None:
        self.programs: dict[int, list[ProgramLine]] = {}
        self._edit: tuple[Port, int] | None = None
        #: The open program's structure so far (entry checks, :mod:`.flow`).
        self._structure = Structure(dry=True)
        #: Compiled code per program: (code, what is left open or None); dropped on edit.
        self._code: dict[int, tuple[Code, str | None]] = {}
        self._words = 0  # buffer words of every program, kept as lines come and go

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
        self.open_key(n, port)

    def open_key(self, key: int, port: Port) -> None:
        """Open the buffer stored under ``key`` for entry: a PROG number, or the key of a
        CS's forward / inverse kinematic buffer (entered, checked, cleared and closed as a
        PROG is)."""
        lines = self.programs.setdefault(key, [])
        self._edit = (port, key)
        self._structure = Structure(dry=True)
        for line in lines:
            self._structure.feed(line)

    def store(self, line: ProgramLine) -> None:
        """One compiled line at the end of the open program.

        Raises:
            ParseError: ERR009, the line breaks the program's structure (``ENDIF`` with no
                ``IF``...); nothing is stored.
        """
        assert self._edit is not None
        trial = self._structure.copy()
        trial.feed(line)
        self._structure = trial
        self.programs[self._edit[1]].append(line)
        self._words += line.words
        self._code.pop(self._edit[1], None)

    def clear(self) -> None:
        """``CLEAR``: empty the open program."""
        assert self._edit is not None
        self._words -= sum(line.words for line in self.programs[self._edit[1]])
        self.programs[self._edit[1]] = []
        self._structure = Structure(dry=True)
        self._code.pop(self._edit[1], None)

    def close(self, port: Port) -> None:
        """``CLOSE`` on ``port``.

        Raises:
            Conflict: ERR009 when a block is left open; entry has ended all the same
                ``[INF]`` (and running the program answers ERR016).
        """
        if self._edit is not None and self._edit[0] is port:
            self._edit = None
            problem = self._structure.unclosed()
            self._structure = Structure(dry=True)
            if problem is not None:
                raise Conflict(f"program structural error: {problem}", pmac_error=STRUCTURAL)

    def code(self, n: int) -> Code | None:
        """Program ``n`` compiled with its jumps (cached until it is edited), or None when it
        does not exist or is empty."""
        lines = self.programs.get(n)
        if not lines:
            return None
        got = self._code.get(n)
        if got is None:
            got = self._code[n] = build(lines)
        return got[0]

    def words(self) -> int:
        """Buffer memory the programs take."""
        return self._words

    def run_of(
        self, cs: int, n: int, emit: Callable[..., Any], vars_: Any = None
    ) -> ProgramRun:
        """A fresh run of program ``n`` for ``cs`` (ERR015 if it does not exist or is open,
        ERR016 if a block in it is not closed)."""
        lines = self.programs.get(n)
        if lines is None or not lines:
            raise Conflict(f"there is no PROG {n}", pmac_error="ERR015")
        if self.editing() == n:
            raise Conflict(f"PROG {n} is open: CLOSE it first", pmac_error="ERR015")
        self.code(n)
        problem = self._code[n][1]
        if problem is not None:
            raise Conflict(f"PROG {n} is improperly structured: {problem}",
                           pmac_error="ERR016")
        return ProgramRun(cs, n, self, emit, vars_)


__all__ = ["N_PROGRAMS", "MotionPrograms", "ProgramRun"]
