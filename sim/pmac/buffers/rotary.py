"""A coordinate system's rotary program buffer, and the one place BREQ is decided.

The rotary buffer is a ring of memory words (seed 000, TUM p337): the host loads program
lines ahead of the executing point while earlier lines run, and executed lines give their
words back, so a 600-word buffer streams any number of lines. Here it is two queues:

* ``pending`` — lines stored but not yet worked through by move planning; their number is
  ``lines_ahead``, what ``PR`` reports and what I16 / I17 are compared with (TSRM p46, p286);
* ``calculated`` — lines planning has worked through whose words are not yet free (they are
  released when execution starts the move of a later line: the move start in
  :mod:`motionsim.sim.pmac.lookahead.execution` pops them).

BREQ ("buffer request", seed 000 and spec §1.2), each edge a ``breq`` event:

* a line sent takes BREQ low, at least momentarily; if fewer than I17 lines are then ahead it
  goes high again at once — so every line loaded below I17 is a low→high pulse (two events at
  the same ``t``), i.e. an interrupt to the host; at I17 or more ahead it stays low and the
  "rotary buffer full" status bit (``??`` word 2 bit 16) is set;
* after a line is calculated, fewer than I16 lines ahead sets BREQ high (and clears the bit);
* ``OPEN ROT`` or a change of the host-addressed CS takes it low, then high if fewer than I17
  lines are ahead (:meth:`RotaryBuffer.reevaluate`).

A new buffer starts with BREQ low ``[INF]`` until one of those rules raises it; one defined
through the REST rotary resource counts as entered with ``OPEN ROT`` (API.md), so it is
re-evaluated at once and an empty buffer asks for lines.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable
from typing import Any

from ...errors import BufferFull
from ...events import EventLog
from ..language.flow_statements import FLOW_TYPES
from .flow import build
from .line_numbers import LineNumbering
from .program import ProgramLine, rotary_check
from .program_run import ProgramRun

#: The fields of the per-line events (:meth:`motionsim.sim.events.EventLog.emit_row`), in
#: the order of ``EVENT_FIELDS``.
_LOADED = ("cs", "n", "text", "words", "lines_ahead")
_BREQ = ("cs", "level")
_CS_N = ("cs", "n")


class RotaryBuffer:
    """The rotary buffer of coordinate system ``cs``, ``size_words`` long.

    Args:
        cs: coordinate system number.
        size_words: size from ``DEFINE ROT``.
        log: the controller's event log.
        thresholds: returns ``(I16, I17)`` now (they may change at any time).
        vars_: the variable store; its ``version`` tells when to call ``thresholds`` again.
        faults: the card's :class:`motionsim.sim.faults.CardFaults` (a rising edge it says
            is lost raises the level without a ``breq`` event or interrupt), or None.
    """

    #: The planning interface of a program run (:class:`.program_run.ProgramRun`): a rotary
    #: buffer has no BLOCKSTART; it interrupts a calculation pass only inside the control
    #: flow of one of its lines (``interrupt``, as a program run does).
    in_block = False

    __slots__ = (
        "cs",
        "size_words",
        "used_words",
        "pending",
        "calculated",
        "n_loaded",
        "breq",
        "full",
        "numbering",
        "_emit",
        "_thresholds",
        "_rise",
        "_vars",
        "_ver",
        "_i16",
        "_i17",
        "_faults",
        "interrupt",
        "_programs",
        "_run",
        "_given",
        "_row",
        "_low",
        "_high",
    )

    def __init__(
        self,
        cs: int,
        size_words: int,
        log: EventLog,
        thresholds: Callable[[], tuple[float, float]],
        vars_: Any,
        faults: Any = None,
        programs: Any = None,
    ) -> None:
        self._faults = faults
        self.interrupt: str | None = None
        #: The fixed programs a line may CALL (:class:`.programs.MotionPrograms`), or None.
        self._programs = programs
        #: The control flow of the line at the head of ``pending`` being worked through.
        self._run: ProgramRun | None = None
        self._given = False  # a part of that line went to planning
        self.cs = cs
        self.size_words = size_words
        self.used_words = 0
        self.pending: deque[tuple[int, ProgramLine]] = deque()
        self.calculated: deque[tuple[int, int]] = deque()
        self.n_loaded = 0
        self.breq = False
        self.full = False
        #: The host's ``first_seq`` numbering of the lines stored
        # (sim/pmac/buffers/line_numbers.py).
        self.numbering = LineNumbering()
        self._emit = log.emit
        self._row = log.emit_row  # the per-line events: line_loaded, breq, line_calculated
        self._low = (cs, False)  # the two breq events' values
        self._high = (cs, True)
        self._thresholds = thresholds
        self._rise: list[Callable[[], Any]] = []
        self._vars = vars_
        self._ver = -1
        self._i16 = 5.0
        self._i17 = 10.0

    def _limits(self) -> None:
        """Refresh the cached I16 / I17 (``vars_.version`` tells when they may have changed)."""
        self._i16, self._i17 = self._thresholds()
        self._ver = self._vars.version

    # -- state ----------------------------------------------------------------------------

    @property
    def lines_ahead(self) -> int:
        """Lines stored but not yet calculated (``PR``)."""
        return len(self.pending)

    @property
    def free_words(self) -> int:
        return self.size_words - self.used_words

    def fits(self, words: int) -> bool:
        """``words`` more fit in the buffer: the one rule every way of storing lines asks
        (a batch is stored all or nothing)."""
        return self.used_words + words <= self.size_words

    def no_room(self, words: int, lines: int = 1) -> BufferFull:
        """The error for ``lines`` lines of ``words`` words that do not :meth:`fits` (ERR006,
        with the words free)."""
        what = f"line of {words} words does" if lines == 1 else f"{lines} lines of {words} words do"
        return BufferFull(
            f"{what} not fit ({self.free_words} words free)",
            pmac_error="ERR006",
            free_words=self.free_words,
        )

    def to_dict(self, open_: bool) -> dict[str, Any]:
        """The API's ``Rotary`` shape."""
        return {
            "size_words": self.size_words,
            "used_words": self.used_words,
            "free_words": self.free_words,
            "lines_ahead": len(self.pending),
            "breq": self.breq,
            "open": open_,
            "full": self.full,
        }

    # -- BREQ -----------------------------------------------------------------------------

    def _set(self, level: bool) -> None:
        if level == self.breq:
            return
        self.breq = level
        if level and self._lost():
            return
        self._row("breq", _BREQ, self._high if level else self._low)
        if level and self._rise:
            waiters, self._rise = self._rise, []
            for cb in waiters:
                cb()

    def _lost(self) -> bool:
        """An injected fault takes this rising edge: the level is high, nobody is told."""
        faults = self._faults
        return faults is not None and faults.active and faults.lose_breq_rise(self.cs)

    def on_rise(self, cb: Callable[[], Any]) -> None:
        """Call ``cb()`` once, at the next rising edge of BREQ (a host's interrupt)."""
        self._rise.append(cb)

    def reevaluate(self) -> None:
        """``OPEN ROT`` / addressed CS changed: low, then high if fewer than I17 ahead (seed
        000). The full bit keeps its hysteresis (TSRM p286): set at I17 or more ahead,
        cleared only below I16, so a re-evaluation between the two leaves it as it was."""
        self._set(False)
        i16, i17 = self._thresholds()
        ahead = len(self.pending)
        if ahead >= i17:
            self.full = True
        elif ahead < i16:
            self.full = False
        if ahead < i17:
            self._set(True)

    # -- loading and planning -------------------------------------------------------------

    def store(self, line: ProgramLine) -> int:
        """Store one line (the caller has checked :meth:`fits`); returns its number ``n``.

        Raises:
            NotSimulated: a control-flow line (:func:`.program.rotary_check`); not stored.
        """
        if line.flow is not None:
            rotary_check(line)
        self.n_loaded = n = self.n_loaded + 1
        pending = self.pending
        pending.append((n, line))
        words = line.words
        self.used_words += words
        ahead = len(pending)
        row = self._row
        row("line_loaded", _LOADED, (self.cs, n, line.text, words, ahead))
        if self.breq:
            self.breq = False
            row("breq", _BREQ, self._low)
        if self._ver != self._vars.version:
            self._limits()
        if ahead < self._i17:
            self.breq = True  # the rising half of the pulse: an interrupt to the host
            if self._faults is not None and self._lost():
                return n  # the rise happened but was never signalled (an injected fault)
            row("breq", _BREQ, self._high)
            if self._rise:
                waiters, self._rise = self._rise, []
                for cb in waiters:
                    cb()
        else:
            self.full = True
        return n

    def take(self) -> tuple[int, ProgramLine] | None:
        """The next line for move planning, or None when planning has caught up.

        A line with control flow (a one-line IF, a CALL, a G/M/T/D code) stays at the head
        of ``pending`` while its flow is followed (:meth:`_follow`): planning takes its parts
        and the lines of the programs it calls, each under the rotary line's number, and the
        next rotary line after it has returned."""
        while self.pending:
            n, line = self.pending[0]
            if line.flow is not None and self._programs is not None and self._jumps(line):
                got = self._follow(n, line)
                if got is not None or self.interrupt is not None:
                    return got
                continue  # the line's flow is done: it has been taken
            item = self.pending.popleft()
            self.calculated.append((item[0], item[1].words))
            return item
        return None

    @staticmethod
    def _jumps(line: ProgramLine) -> bool:
        return any(isinstance(s, FLOW_TYPES) for s in line.flow or ())

    def _follow(self, n: int, line: ProgramLine) -> tuple[int, ProgramLine] | None:
        """The next part of line ``n``'s control flow; None when it is done (the line is
        then taken out of ``pending``) or when the pass must end (``interrupt`` says why:
        a WAIT or the double jump-back in a called program, or a run-time error)."""
        run = self._run
        if run is None:
            code, _ = build([line])
            emit = self._emit

            def emit_here(type_: str, **fields: Any) -> None:
                if fields.get("prog") == 0:  # the rotary line itself (not a called PROG)
                    fields["n"] = n
                emit(type_, **fields)

            run = self._run = ProgramRun(self.cs, 0, self._programs, emit_here, self._vars,
                                         code=code)
        got = run.take()
        if got is not None:
            self._given = True
            return n, got[1]
        why = run.interrupt
        if why in ("suspend", "wait", "error"):
            if why == "error":
                self._end_flow()
            self.interrupt = why
            return None
        if why == "stop":
            self._end_flow()
            self._emit("program_error", cs=self.cs, prog=0, n=n,
                       reason="STOP in a program called from a rotary buffer is not simulated")
            self.interrupt = "error"
            return None
        self._end_flow()  # "end": back in the rotary buffer, after this line
        return None

    def _end_flow(self) -> None:
        """The head line's flow is done: it leaves ``pending``; a line none of whose parts
        reached planning (a false one-line IF) is calculated here, with the I16 rule."""
        self._run = None
        n, line = self.pending.popleft()
        self.calculated.append((n, line.words))
        if not self._given:
            self.line_calculated(n)
        self._given = False

    def line_calculated(self, n: int | None = None) -> int:
        """Planning has worked through line ``n``: the I16 rule, written here only (seed 000,
        TSRM p286): fewer than I16 lines ahead clears the full bit and raises BREQ.

        Without ``n`` (as :meth:`take_simple`): the next line is taken here first, one whose
        calculation emits nothing (a plain move line), so the event and the rule follow at
        once. Returns the line's number."""
        if n is None:
            n, line = self.pending.popleft()
            self.calculated.append((n, line.words))
        self._row("line_calculated", _CS_N, (self.cs, n))
        if self._ver != self._vars.version:
            self._limits()
        if len(self.pending) < self._i16:
            self.full = False
            if not self.breq:
                self._set(True)
        return n

    #: Take the next line when its calculation emits nothing (a plain move line) and return
    #: its number, the ``line_calculated`` event and the I16 rule following at once (one call
    #: on the streaming path).
    take_simple = line_calculated

    def clear(self) -> None:
        """``CLEAR`` with the rotary buffers open: erase this buffer's lines not yet
        calculated (those planning has calculated run on; a line whose control flow is being
        followed stays whole) and re-evaluate BREQ as at ``OPEN ROT`` ``[INF]``: the Turbo
        SRM's CLEAR page was not found (spec §11.12); the card's CLEAR "erases the open
        buffer" (spec §11.8) and a PComm32 host sends ``OPEN ROT`` ``CLEAR`` before
        streaming a new program."""
        keep = 1 if self._run is not None and self.pending else 0
        while len(self.pending) > keep:
            self.used_words -= self.pending.pop()[1].words
        self.reevaluate()

    def free_calculated(self) -> None:
        """Release every calculated line (motion stopped, or lookahead discarded by ``A``)."""
        while self.calculated:
            self.used_words -= self.calculated.popleft()[1]


__all__ = ["RotaryBuffer"]
