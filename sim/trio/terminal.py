"""The command line: process 0, channel 0, the ``>>`` prompt.

A line typed at the command line runs at once, at the current simulated instant (it never
moves a virtual clock): ``? MTYPE AXIS(0)`` answers ``1.0000`` (four decimals, spec §9.4),
``VR(5)=2`` answers nothing, ``MOVE(10) AXIS(0)`` buffers a move for process 0.

A move that cannot be buffered — process 0's process buffer is full — **locks the terminal**
(TN20: the terminal "locks up" until the process buffer becomes free): the command's
:class:`~motionsim.sim.controller.Reply` stays pending, a ``terminal`` event reports ``locked:
true``, process 0 is ``blocked`` on the line, and every later command queues behind it. When the
move is buffered the rest of the line runs, the reply completes (a ``terminal_reply`` event with
``command``, ``reply``, ``error``), ``terminal`` ``locked: false`` follows, and the queued
commands run in order — each may lock the terminal again. Every command that was answered
pending gets its ``terminal_reply`` event.

Replies: printed lines joined with ``"\\r\\n"`` (no prompt, no echo — the telnet adapter adds
those). Errors: ``error`` holds the message in the controller's ``%[Process 0:Line 0] - ...``
style (``[BK]``, :mod:`motionsim.sim.trio.card.basic_errors`). Program-only statements (``WAIT``,
``WA``)
are refused; local variables cannot be used at the command line (TJ1P-26). ``PROCESS`` answers
the table of running programs, ``HALT`` stops them all; ``PRINT #n`` with n > 0 goes to that
channel, not to the reply; a running program's own output reaches the command line through
:mod:`motionsim.sim.trio.card.output`.
"""

from __future__ import annotations

from collections import deque
from typing import TYPE_CHECKING, Any

from ..controller import Reply
from ..errors import NotSimulated, ParseError
from .card import basic_errors as msg
from .card.basic_errors import BasicError, error_line
from .language.compiler import HALT, Block, Code, compile_program
from .language.parser import parse_program
from .motion.buffers import Waiter
from .run.context import Context

if TYPE_CHECKING:
    from .controller import TrioController

#: Operations a single command line may execute (a FOR loop typed with ``:`` included).
MAX_STEPS = 100_000


class _Running:
    """A command line part-way through: where to go on once its move is buffered."""

    __slots__ = ("reply", "code", "pc", "out", "pending")

    def __init__(self, reply: Reply, code: Code) -> None:
        self.reply = reply
        self.code = code
        self.pc = 0
        self.out: list[str] = [""]
        self.pending = False


class CommandLine:
    """Process 0 of one controller: shared by the REST terminal and every telnet session."""

    def __init__(self, ctrl: TrioController) -> None:
        self.ctrl = ctrl
        self._current: _Running | None = None
        self.ctx = Context(ctrl, 0, self._output, command_line=True)
        self.queue: deque[Reply] = deque()
        self.locked = False
        self._draining = False  # a line is running: a new one queues behind it
        self._waiter: Waiter | None = None

    def _output(self, text: str, newline: bool, channel: float | None = None) -> None:
        """A PRINT at the command line is its reply; ``PRINT #n`` with n > 0 goes to that
        channel (:mod:`motionsim.sim.trio.card.output`)."""
        if channel is not None and self.ctrl.channels.check(channel) != 0:
            self.ctrl.channels.write(0, int(channel), text)
            return
        run = self._current
        assert run is not None
        run.out[-1] += text
        if newline:
            run.out.append("")

    # -- public ----------------------------------------------------------------------------

    def command(self, text: str) -> Reply:
        """Run one line; the reply is done at once unless the terminal is (or becomes) locked
        or another line is running. Lines run strictly in the order received: one typed while
        a line runs (from a host's callback on that line's events or reply) or while the
        terminal is locked waits in the queue behind the others."""
        reply = Reply(text)
        self.queue.append(reply)
        if not self._draining and not self.locked:
            self._drain(first=reply)
        return reply

    def _drain(self, first: Reply | None = None) -> None:
        """Run the queued lines in order until the queue is empty or a line locks the
        terminal; ``first`` is the line its own ``command`` call runs (answered at once)."""
        self._draining = True
        try:
            while self.queue and not self.locked:
                reply = self.queue.popleft()
                self._start(reply, pending=reply is not first)
        finally:
            self._draining = False

    def state(self) -> dict[str, Any]:
        """``{"locked", "pending": [commands waiting, the blocked one first]}``."""
        pending = [self._current.reply.command] if self.locked and self._current else []
        return {"locked": self.locked, "pending": pending + [r.command for r in self.queue]}

    def reset(self) -> None:
        if self._waiter is not None:
            self._waiter.cancel()
        for r in [self._current.reply] if self._current else []:
            r.resolve("", error_line(0, 0, "Controller reset"), self.ctrl.env.now)
        for r in self.queue:
            r.resolve("", error_line(0, 0, "Controller reset"), self.ctrl.env.now)
        self.queue.clear()
        self._current = None
        self.locked = False

    # -- running a line ---------------------------------------------------------------------

    def _start(self, reply: Reply, pending: bool = False) -> None:
        try:
            ctrl = self.ctrl
            code = compile_program(parse_program(reply.command, ctrl.model.name),
                                   shared=ctrl.declared, functions=ctrl.functions())
        except (ParseError, NotSimulated) as exc:
            column = exc.details.get("column")
            col = f" at column {column}" if column else ""
            if isinstance(exc, NotSimulated):
                reply.detail = ("not_simulated", exc.message + col)
            self._complete_with(reply, "", error_line(0, 0, exc.message + col), pending)
            return
        run = _Running(reply, code)
        run.pending = pending
        self._current = run
        self._go(run)

    def _go(self, run: _Running) -> None:
        code, ctx = run.code, self.ctx
        ops, n = code.ops, len(code.ops)
        steps = 0
        error: str | None = None
        try:
            while run.pc < n:
                steps += 1
                if steps > MAX_STEPS:
                    raise BasicError(msg.TOO_MANY_STEPS)
                r = ops[run.pc](ctx)
                if r is None:
                    run.pc += 1
                elif r.__class__ is int:
                    run.pc = r
                elif r.__class__ is Block:
                    run.pc += 1
                    self._lock(run, r.move)
                    return
                elif r is HALT:
                    break
                else:
                    raise BasicError(msg.NOT_AT_COMMAND_LINE)
        except BasicError as exc:
            error = error_line(0, 0, exc.message)
        self._current = None
        lines = run.out[:-1] if run.out[-1] == "" else run.out
        self._complete_with(run.reply, "\r\n".join(lines), error, run.pending)

    def _lock(self, run: _Running, move: Any) -> None:
        placed = self.ctrl.buffers.place_or_wait(move, lambda _placed: self._placed(run))
        assert isinstance(placed, Waiter)
        self._waiter = placed
        run.pending = True
        log = self.ctrl.log
        text = run.code.text(run.pc - 1)
        if not self.locked:
            self.locked = True
            log.emit("terminal", locked=True)
        log.emit("process", process=0, state="blocked", line=0, blocked_on=text)

    def _placed(self, run: _Running) -> None:
        self._waiter = None
        self.ctrl.log.emit("process", process=0, state="running", line=0)
        self._current = run
        self._go(run)

    def _complete_with(self, reply: Reply, text: str, error: str | None, pending: bool) -> None:
        now = self.ctrl.env.now
        reply.resolve(text, error, now)
        if pending:
            self.ctrl.log.emit("terminal_reply", command=reply.command, reply=text, error=error)
        if self.locked and self._current is None:
            self.locked = False
            self.ctrl.log.emit("terminal", locked=False)
        if not self._draining and not self.locked:
            self._drain()


__all__ = ["CommandLine"]
