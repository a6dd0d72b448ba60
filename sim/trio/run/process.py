"""A Trio BASIC program running in a process: one SimPy process per running program.

Timing model (the statements-per-slice figure is not documented anywhere reachable,
spec §9.6 ``[INF]``): every statement the interpreter executes costs ``statement_s`` of
simulated time (config ``statement_us``, default 100 µs: about ten statements per 1 ms
servo period); the jumps that structure adds (ELSE reached at the end of THEN) cost nothing.
A statement's effect happens when it starts; the next one starts ``statement_s`` later.
Processes run concurrently and independently (no shared slice budget is modelled).

Waiting, without a SimPy event per servo period:

* a move line whose process buffer is full: the process emits ``process`` ``blocked`` with
  ``blocked_on`` (the line's text) and waits — even if only for one servo period — until
  :mod:`motionsim.sim.trio.motion.buffers` has placed its move, then emits ``running`` and goes on;
* ``WAIT IDLE`` / ``WAIT LOADED``: woken by the buffer change that satisfies it;
* ``WAIT UNTIL c``: ``c`` is re-tested once per servo period (spec §1.6 ``[BK]``);
* ``WA(ms)``: a timeout;
* any of these inside a library FUNCTION the statement calls: the same wait, seeing the
  function's names, then the statement runs again and the call goes on after its wait
  (:class:`~motionsim.sim.trio.language.functions.Suspend`).

``PRINT`` in a program writes to the process' OUTDEVICE (channel 0, the command line, unless
changed) or to the channel of ``PRINT #n``: see :mod:`motionsim.sim.trio.card.output`.

A runtime error stops this process only: a ``process`` event with ``state`` ``stopped``, the
``line`` and an ``error`` message in the controller's style
(:mod:`motionsim.sim.trio.card.basic_errors`); the same line is printed on channel 0. Once
``ON BASICERROR GOTO label`` has run, the error (or a ``STOP "prog"`` of it, RUN_ERROR 31)
instead continues at the label with RUN_ERROR / ERROR_LINE set, reported by a ``basic_error``
event; an error inside the handler stops the process unless it ran ON BASICERROR again
(spec §11.3, :mod:`~.branches`).
"""

from __future__ import annotations

from collections.abc import Generator
from typing import TYPE_CHECKING, Any

import simpy

from ...simpy_adapter import Due, succeed_at
from ..card.basic_errors import RUN_ERROR_STOPPED, BasicError, error_line
from ..language.compiler import HALT, Block, Code, Poll, Sleep, WaitFor
from ..language.functions import Suspend, in_function
from ..motion.buffers import Waiter, schedule_at
from .context import Context

if TYPE_CHECKING:
    from ..controller import TrioController

#: The fields of a ``process`` event reporting ``running`` / ``blocked`` (stored by
#: :meth:`motionsim.sim.events.EventLog.emit_row`: once or twice per move line that waits).
RUNNING_KEYS = ("process", "state", "line")
BLOCKED_KEYS = ("process", "state", "line", "blocked_on")


class BasicProcess:
    """Program ``program`` running as process ``number``."""

    def __init__(self, ctrl: TrioController, number: int, program: str, code: Code) -> None:
        self.ctrl = ctrl
        self.number = number
        self.program = program
        self.code = code
        self.state = "running"
        self.line = code.lines[0] if code.lines else 0
        self.pc = 0
        self.blocked_on: str | None = None
        self.error: str | None = None
        self._pending: dict[int, str] = {}  # channel -> text of a line not yet ended
        self.ctx = Context(ctrl, number, self._output)
        self._withdraw: Any = None
        #: a move line waiting for its placement: the event the program resumes on, and the
        #: line's statement time still to run once placed (see _blocked)
        self._awaiting: simpy.Event | None = None
        self._await_s = 0.0
        self._texts: dict[int, str] = {}  # blocked_on texts by pc
        self.sim = ctrl.env.process(self._run())

    # -- output ----------------------------------------------------------------------------

    def _output(self, text: str, newline: bool, channel: float | None = None) -> None:
        ch = self.ctx.outdevice if channel is None else self.ctrl.channels.check(channel)
        line = self._pending.pop(ch, "") + text
        if newline:
            self.ctrl.channels.write(self.number, ch, line)
        else:
            self._pending[ch] = line

    # -- the interpreter loop ----------------------------------------------------------------

    def _run(self):
        code, ctx, log, env = self.code, self.ctx, self.ctrl.log, self.ctrl.env
        ops, costs, lines = code.ops, code.costs, code.lines
        dt = self.ctrl.statement_s
        number = self.number
        n = len(ops)
        pc = 0
        suspended: Suspend | None = None
        ctx.frame.can_wait = True  # a statement's library calls may wait (functions.py)
        log.emit("process", process=number, state="running", line=self.line)
        while True:  # once more for each error / STOP an ON BASICERROR handler takes
            try:
                if suspended is not None:  # a function waits: then its statement runs again
                    sus, suspended = suspended, None
                    yield from self._wait_in_function(sus, pc)
                while pc < n:
                    self.pc = pc
                    cost = costs[pc]
                    r = ops[pc](ctx)
                    if r is None:
                        pc += 1
                    elif r.__class__ is int:
                        pc = r
                    elif r.__class__ is Block:
                        self.line = lines[pc]
                        ev = self._blocked(r.move, pc, dt if cost else 0.0)
                        pc += 1
                        if ev is not None:
                            yield ev
                            if cost:
                                continue  # the statement's time ran in the wait (_unblocked)
                            self._running()
                    elif r is HALT:
                        break
                    elif r.__class__ is Sleep:
                        yield env.timeout(r.seconds)
                        pc += 1
                    elif r.__class__ is WaitFor:
                        yield from self._wait_for(r)
                        pc += 1
                    elif r.__class__ is Poll:
                        yield from self._poll(r)
                        pc += 1
                    else:
                        pc += 1
                    if cost:
                        yield Due(env, env._now + dt)  # env.timeout(dt), one call less
                self.line = lines[min(pc, n - 1)] if n else 0
                self._finish(None)
                return
            except Suspend as sus:
                if sus.wait is HALT:  # STOP inside a function: the program ends there
                    self.line = lines[pc]
                    self._finish(None)
                    return
                suspended = sus
            except BasicError as exc:
                self.line = lines[pc] if pc < n else self.line
                target = self._trapped(exc.number, exc.message, self.line)
                if target is None:
                    self._finish(error_line(number, self.line, exc.message))
                    return
                pc = target
            except simpy.Interrupt as intr:
                if not (isinstance(intr.cause, tuple) and intr.cause[0] == "trap"):
                    return  # stop() has already withdrawn the wait and reported the stop
                pc = intr.cause[1]  # STOP "prog" with a handler armed: go on there

    def _wait_in_function(self, sus: Suspend, pc: int) -> Generator[Any, Any, None]:
        """A library function called by the statement at ``pc`` waits (functions.py): the
        process waits as for the same statement inline, seeing the function's names (a WAIT
        UNTIL condition reads its locals), then the statement runs again and the call goes on
        after its wait. A move into a full buffer reports the library line it waits at."""
        ctx, env = self.ctx, self.ctrl.env
        own = (ctx.locals, ctx.loops, ctx.selected, ctx.data_bytes, ctx.calls, ctx.frame)
        assert sus.state is not None
        (ctx.locals, ctx.loops, ctx.selected, ctx.data_bytes, ctx.calls,
         ctx.frame) = sus.state
        r = sus.wait
        try:
            if r.__class__ is Block:
                self.line = self.code.lines[pc]
                ev = self._blocked(r.move, pc, 0.0, sus.text)  # its time: when it runs again
                if ev is not None:
                    yield ev
                    self._running()
            elif r.__class__ is Sleep:
                yield env.timeout(r.seconds)
            elif r.__class__ is WaitFor:
                yield from self._wait_for(r)
            elif r.__class__ is Poll:
                yield from self._poll(r)
        except BasicError as exc:  # a condition tested while waiting failed
            err = in_function(exc, sus.where)
            if err is exc:
                raise
            raise err from None
        finally:
            (ctx.locals, ctx.loops, ctx.selected, ctx.data_bytes, ctx.calls,
             ctx.frame) = own
        own[5].replaying = True

    def _wait_for(self, r: WaitFor) -> Generator[Any, Any, None]:
        ev = self.ctrl.env.event()
        self._withdraw = self.ctrl.buffers.when(r.predicate, ev.succeed)
        yield ev
        self._withdraw = None

    def _trapped(self, number: int, message: str, line: int) -> int | None:
        """ON BASICERROR: the handler's pc after an error (or a STOP, RUN_ERROR 31) at
        ``line``, with a ``basic_error`` event; None when no handler takes it."""
        target = self.ctx.enter_handler(number, line)
        if target is None:
            return None
        self.ctrl.log.emit("basic_error", process=self.number, line=line, run_error=number,
                           error=message, handler_line=self.code.lines[target]
                           if target < len(self.code.lines) else line)
        return target

    def _blocked(self, move: Any, pc: int, cost_s: float,
                 text: str | None = None) -> simpy.Event | None:
        """The move line at ``pc`` found its process buffer full: wait for the servo period
        that places ``move`` (None: placed at once, no wait). The process reports ``blocked``
        now and ``running`` when the move is placed; the line's statement time ``cost_s``
        runs from that instant, so with a cost the returned event is the end of it and
        :meth:`_unblocked` reports ``running`` on the way (one resumption of the program
        instead of two; the same instants and the same order of events as a resumption at
        the placement followed by a statement timeout). ``text``: what it is blocked on, when
        not the line at ``pc`` (a library function's move line)."""
        env = self.ctrl.env
        ev = env.event()
        buffers = self.ctrl.buffers
        placed = (buffers.place_or_wait(move, self._unblocked, True) if cost_s
                  else buffers.place_or_wait(move, ev.succeed))
        if not isinstance(placed, Waiter):
            return None
        self._withdraw = placed.cancel
        self._awaiting, self._await_s = ev, cost_s
        if text is None:
            text = self._texts.get(pc)
            if text is None:
                text = self._texts[pc] = self.code.text(pc)
        self.state, self.blocked_on = "blocked", text
        self.ctrl.log.emit_row("process", BLOCKED_KEYS,
                               (self.number, "blocked", self.line, text))
        return ev

    def _unblocked(self, _event: Any) -> None:
        """Where the program resumes after its move was placed, at this place in the instant's
        order of events (``MotionBuffers._resume_placed``): ``running``, then the line's
        statement time, at whose end the program goes on (unless it was stopped meanwhile)."""
        ev = self._awaiting
        if ev is None:
            return
        self._running()
        env = self.ctrl.env
        succeed_at(env, ev, env._now + self._await_s)

    def _running(self) -> None:
        self._withdraw = None
        self._awaiting = None
        self.state, self.blocked_on = "running", None
        self.ctrl.log.emit_row("process", RUNNING_KEYS, (self.number, "running", self.line))

    def _poll(self, r: Poll):
        env, clock = self.ctrl.env, self.ctrl.clock
        while True:
            ev = env.event()
            schedule_at(env, clock.t(clock.after(env.now)), lambda _e, ev=ev: ev.succeed())
            yield ev
            if r.predicate():
                return

    def _withdraw_wait(self) -> None:
        self._awaiting = None
        if self._withdraw is not None:
            self._withdraw()
            self._withdraw = None

    def _finish(self, error: str | None) -> None:
        for ch, text in sorted(self._pending.items()):
            self.ctrl.channels.write(self.number, ch, text)
        self._pending.clear()
        if error is not None:
            self.ctrl.channels.write(self.number, 0, error)
            if not self.ctx.run_error:
                self.ctx.run_error, self.ctx.error_line = 1, self.line
        self.state, self.blocked_on, self.error = "stopped", None, error
        fields: dict[str, Any] = {"process": self.number, "state": "stopped", "line": self.line}
        if error is not None:
            fields["error"] = error
        self.ctrl.log.emit("process", **fields)

    # -- control ---------------------------------------------------------------------------

    def stop(self, trap: bool = False) -> None:
        """Stop the program at once: the wait it is in (a move line, WAIT, WA) is withdrawn and
        ``stopped`` is reported at the current instant. With ``trap`` (``STOP "prog"`` from
        BASIC) and an ON BASICERROR handler armed, the program goes on in its handler with
        RUN_ERROR 31 instead (spec §11.3 ``[INF]``)."""
        if self.state == "stopped" or not self.sim.is_alive:
            return
        self._withdraw_wait()
        if self.pc < len(self.code.lines):
            self.line = self.code.lines[self.pc]
        if trap:
            target = self._trapped(RUN_ERROR_STOPPED, "Program stopped", self.line)
            if target is not None:
                self.state, self.blocked_on = "running", None
                self.sim.interrupt(("trap", target))
                return
        self._finish(None)
        self.sim.interrupt("stop")

    def current_line(self) -> int:
        """The program line being executed (the last one, once stopped)."""
        if self.state == "stopped" or self.pc >= len(self.code.lines):
            return self.line
        return self.code.lines[self.pc]

    def describe(self) -> dict[str, Any]:
        """The API.md process resource."""
        out: dict[str, Any] = {
            "process": self.number,
            "program": self.program,
            "state": self.state,
            "line": self.current_line(),
            "pmove": self.ctrl.buffers.pmove(self.number),
        }
        if self.blocked_on is not None:
            out["blocked_on"] = self.blocked_on
        if self.error is not None:
            out["error"] = self.error
        return out


__all__ = ["BasicProcess"]
