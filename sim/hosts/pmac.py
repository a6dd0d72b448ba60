"""Host programs that stream a motion program into a Turbo PMAC rotary buffer.

Each host is a SimPy process on the controller's own environment that calls only the
controller's public methods (``load_lines``, ``rotary``, ``run``) and listens to its event log
(``breq`` edges), exactly as host software sees the card. Three strategies from the manual's
"Staying Ahead of Executing Line":

* :class:`PrPollingHost` — asks ``PR`` (lines ahead) every poll period; below the low-water
  mark it loads until the high-water mark ("get 1000 lines ahead, and then start again when the
  program has caught up to within 500 lines").
* :class:`BreqInterruptHost` — waits for the BREQ interrupt; after its interrupt latency the
  service routine loads lines. BREQ rises when a loaded line leaves fewer than I17 lines ahead
  and when execution leaves fewer than I16; the PC's interrupt controller is edge-triggered, so
  an edge arriving while the routine runs (interrupts masked) is lost — a routine that loads
  once and returns with BREQ still high gets no further interrupt (a *missed BREQ*). With
  ``recheck_breq`` the routine keeps loading until BREQ reads low, the manual's safe pattern.
* :class:`NaiveHost` — sends as fast as the link allows, retrying when the buffer is full.

Hosts add their own events to the controller's log so a run can be explained afterwards
(they are not controller events and never appear on a real card):

* ``host_write`` — ``host``, ``cs``, ``lines`` (batch size), ``sent`` (lines sent so far),
  ``lines_ahead`` after the write.
* ``host_irq`` — ``host``, ``cs``, ``missed`` (bool), ``latency_s``: a BREQ edge serviced after
  ``latency_s`` (``missed`` false) or lost while the interrupt was masked (``missed`` true).
* ``host_done`` — ``host``, ``cs``, ``sent``: the whole program has been sent.
* ``host_pr`` — ``host``, ``cs``, ``lines_ahead``, ``reply_s``: a ``PR`` sent as a terminal
  command was answered ``reply_s`` after the card received it (PR-polling host with
  ``via_terminal``). The card answers host commands at the end of a background cycle, so this
  grows when PLC 0 and the RTI leave the background little processor time (seed 003).
* ``host_timeout`` — ``host``, ``cs``, ``command``, ``waited_s``: no reply within the host's
  reply timeout (the host gives up on that poll and polls again on its period).
* ``host_stopped`` — ``host``, ``cs``, ``reason``: the controller refused the host (the
  watchdog tripped: a tripped card answers nothing), the host stops.

Write path (``write_via``): ``direct`` puts a batch straight into the rotary buffer
(``load_lines``, a stand-in with no command processing: a busy card does not delay it).
``terminal`` writes as host software does, through the card's command line on a port of the
host's own: ``&cs B0`` and ``&cs OPEN ROT`` once (``&cs R`` to start the program), then each
program line as one command line, each answered at the end of a background cycle (a program
line per command line ``[INF]``: the manual stores the program statements between two on-line
commands as one line, so joining several lines in one command would merge them into one
program line). The host keeps at most one
command awaiting its reply on its port; ``host_write`` then carries ``reply_s`` (command
sent → answered, the host's write latency) for its one line. A line answered ERR006 did not
fit: the host stops that refill and tries later. A line unanswered after ``reply_timeout_s``
gives a ``host_timeout``; the host sends nothing more on the port until that line's fate is
known (a late answer still counts the line), so a tripped card silences the writes with
timeouts, as a card that stopped communicating does. ``lines_ahead`` / BREQ after a terminal
write are read from the card's status (dual-ported RAM and the BREQ line) ``[INF]``.
"""

from __future__ import annotations

import random
from collections.abc import Generator, Sequence
from typing import Any, NamedTuple

from ..errors import BufferFull, Halted
from .distributions import Delay, fixed

_ZERO = fixed(0.0)

WRITE_VIA = ("direct", "terminal")


class WriteResult(NamedTuple):
    """What a terminal write leaves: the shape of ``LoadResult`` the hosts read."""

    accepted: int
    stored: int
    lines_ahead: int
    free_words: int
    breq: bool


class PmacHost:
    """Common part: the program to send, the write over the link, starting the program.

    Args:
        name: the host's name in ``host_*`` events.
        controller: a PMAC controller (``load_lines``, ``rotary``, ``run``, ``env``, ``log``).
        cs: coordinate system whose rotary buffer is fed.
        lines: the whole program, in order.
        rng: this host's seeded generator.
        write_latency: time one write takes to reach the card (link + host overhead).
        start_program: send ``&cs B0 R`` once the first fill is loaded (the host starts it).
        write_via: ``direct`` (``load_lines``) or ``terminal`` (command lines on the host's
            port, see the module docstring).
        reply_timeout_s: how long the host waits for a reply on its port before giving up
            (``host_timeout``).
    """

    def __init__(
        self,
        name: str,
        controller: Any,
        cs: int,
        lines: Sequence[str],
        rng: random.Random,
        *,
        write_latency: Delay = _ZERO,
        start_program: bool = True,
        write_via: str = "direct",
        reply_timeout_s: float = 1.0,
    ) -> None:
        if write_via not in WRITE_VIA:
            raise ValueError(f"write_via must be one of {WRITE_VIA}, not {write_via!r}")
        if reply_timeout_s <= 0:
            raise ValueError("reply_timeout_s must be > 0")
        self.name = name
        self.controller = controller
        self.env = controller.env
        self.log = controller.log
        self.cs = cs
        self.lines = list(lines)
        self.rng = rng
        self.write_latency = write_latency
        self.start_program = start_program
        self.sent = 0
        self.writes = 0
        self.done_t: float | None = None
        self._started = False
        self.process = None
        self.stall_until = 0.0
        self.stopped: str | None = None
        self.write_via = write_via
        self.reply_timeout_s = reply_timeout_s
        self.port: Any = None
        self.timeouts = 0
        self.write_replies: list[float] = []
        self._opened = False
        self._line_in_flight: tuple[Any, float] | None = None

    def stall(self, until_s: float) -> None:
        """Fault: the host does nothing until ``until_s`` (a busy or paused PC)."""
        self.stall_until = max(self.stall_until, until_s)

    @property
    def remaining(self) -> int:
        """Lines still to send (0 once the host has stopped: it will send nothing more)."""
        return 0 if self.stopped is not None else len(self.lines) - self.sent

    def stop(self, reason: str) -> None:
        """The controller refused the host for good (``Halted``): stop, with a ``host_stopped``."""
        if self.stopped is None:
            self.stopped = reason
            self.log.emit("host_stopped", host=self.name, cs=self.cs, reason=reason)

    def start(self) -> None:
        """Start the host's SimPy process."""
        self.process = self.env.process(self._run())

    def _run(self) -> Generator[Any, Any, None]:  # pragma: no cover - overridden
        raise NotImplementedError
        yield

    def write(self, count: int) -> Generator[Any, Any, Any]:
        """Load up to ``count`` lines in one write after the link delay.

        A batch that does not fit (``BufferFull``) is halved until it does; returns the
        ``LoadResult`` or ``None`` when not even one line fits.
        """
        if self.env.now < self.stall_until:
            yield self.env.timeout(self.stall_until - self.env.now)
        delay = self.write_latency.draw(self.rng)
        if delay > 0:
            yield self.env.timeout(delay)
        if self.write_via == "terminal":
            return (yield from self._write_terminal(count))
        count = min(count, self.remaining)
        while count > 0 and self.stopped is None:
            batch = self.lines[self.sent : self.sent + count]
            try:
                res = self.controller.load_lines(self.cs, batch, first_seq=self.sent + 1)
            except BufferFull:
                count //= 2
                continue
            except Halted as exc:
                self.stop(str(exc))
                return None
            self.sent += count
            self.writes += 1
            self.log.emit(
                "host_write",
                host=self.name,
                cs=self.cs,
                lines=count,
                sent=self.sent,
                lines_ahead=res.lines_ahead,
            )
            if self.remaining == 0:
                self._finish()
            return res
        return None

    # -- the host's command port ----------------------------------------------------------

    def command(self, text: str) -> Generator[Any, Any, Any]:
        """Send ``text`` on the host's port and wait for the answer; the done ``Reply``, or
        ``None`` (no answer within ``reply_timeout_s``: ``host_timeout``; or the card refused
        the host: ``host_stopped``)."""
        t_sent = self.env.now
        reply = self._send(text)
        if reply is None:
            return None
        answered = yield from self._await(reply, t_sent)
        return reply if answered else None

    def _send(self, text: str) -> Any:
        """Put ``text`` on the host's port (opened on first use); the ``Reply``, or ``None``
        when the card refused the host (``host_stopped``)."""
        if self.port is None:
            self.port = self.controller.open_port(self.name)
        try:
            return self.controller.terminal(text, self.port)
        except Halted as exc:
            self.stop(str(exc))
            return None

    def _await(self, reply: Any, t_sent: float) -> Generator[Any, Any, bool]:
        """Wait up to ``reply_timeout_s`` for ``reply``; a ``host_timeout`` if it stays silent."""
        env = self.env
        if not reply.done:
            answered = env.event()
            reply.add_done_callback(lambda _r: answered.triggered or answered.succeed())
            yield answered | env.timeout(self.reply_timeout_s)
        if reply.done:
            return True
        self.timeouts += 1
        self.log.emit(
            "host_timeout", host=self.name, cs=self.cs, command=reply.command,
            waited_s=env.now - t_sent,
        )  # fmt: skip
        return False

    def _refused(self, command: str, waited_s: float, error: str) -> None:
        """``command`` was answered with an error: a ``host_timeout`` carrying ``error``."""
        self.log.emit(
            "host_timeout", host=self.name, cs=self.cs, command=command, waited_s=waited_s,
            error=error,
        )  # fmt: skip

    def _write_terminal(self, count: int) -> Generator[Any, Any, Any]:
        """Up to ``count`` lines, one command line each, one awaiting its answer at a time.

        Returns a :class:`WriteResult` when at least one line was stored, else ``None``.
        """
        stored = 0
        if self._line_in_flight is not None:
            # a line that timed out earlier: nothing more goes out until its answer comes
            reply, t_sent = self._line_in_flight
            if not (yield from self._await(reply, t_sent)):
                return None
            self._line_in_flight = None
            if self._line_answered(reply, t_sent):
                stored += 1
                count -= 1
            elif reply.error:
                return None
        if not self._opened and self.stopped is None and self.remaining > 0:
            if self.start_program and not self._started:
                pointed = yield from self.command(f"&{self.cs}B0")
                if pointed is None or pointed.error:
                    return None
            opened = yield from self.command(f"&{self.cs}OPEN ROT")
            if opened is None or opened.error:
                return None
            self._opened = True
        while stored < count and self.remaining > 0 and self.stopped is None:
            t_sent = self.env.now
            reply = self._send(self.lines[self.sent])
            if reply is None:
                break
            if not (yield from self._await(reply, t_sent)):
                self._line_in_flight = (reply, t_sent)
                break
            if not self._line_answered(reply, t_sent):
                break  # ERR006: no room now; the host tries again later
            stored += 1
        return self._status(stored) if stored else None

    def _line_answered(self, reply: Any, t_sent: float) -> bool:
        """Account one answered program line; False when the card refused it."""
        if reply.error:
            return False
        t_done = reply.t_done if reply.t_done is not None else self.env.now
        self.sent += 1
        self.writes += 1
        self.write_replies.append(t_done - t_sent)
        self.log.emit(
            "host_write", host=self.name, cs=self.cs, lines=1, sent=self.sent,
            lines_ahead=self.lines_ahead(), reply_s=t_done - t_sent,
        )  # fmt: skip
        if self.remaining == 0:
            self._finish()
        return True

    def _status(self, stored: int) -> WriteResult:
        rot = self.controller.rotary(self.cs) or {}
        return WriteResult(
            stored, stored, int(rot.get("lines_ahead", 0)), int(rot.get("free_words", 0)),
            bool(rot.get("breq", False)),
        )  # fmt: skip

    def start_program_once(self) -> Generator[Any, Any, None]:
        """``&cs B0 R`` the first time it is called (if this host starts the program).

        Through the terminal the host pointed the CS at its rotary buffer (``&cs B0``) before
        ``OPEN ROT`` — with the buffers open ``B0`` would be a move of axis B — and now sends
        ``&cs R``, which acts on-line while they are open; an error answer is a
        ``host_timeout`` with ``error``.
        """
        if self._started or not self.start_program or not self.sent or self.stopped is not None:
            return
        self._started = True
        if self.write_via == "terminal":
            command = f"&{self.cs}R"
            t_sent = self.env.now
            reply = yield from self.command(command)
            if reply is not None and reply.error:
                self._refused(command, self.env.now - t_sent, reply.error)
            return
        try:
            self.controller.run(self.cs)
        except Halted as exc:
            self.stop(str(exc))

    def _finish(self) -> None:
        if self.done_t is None:
            self.done_t = self.env.now
            self.log.emit("host_done", host=self.name, cs=self.cs, sent=self.sent)

    def lines_ahead(self) -> int:
        """What ``PR`` answers: lines loaded but not yet calculated."""
        rot = self.controller.rotary(self.cs)
        return int(rot["lines_ahead"]) if rot else 0


class PrPollingHost(PmacHost):
    """Polls ``PR`` every ``poll_period_s``; refills from ``low_water`` up to ``high_water``.

    Args:
        poll_period_s: time between polls (measured from poll start to poll start).
        pr_latency: round trip of the ``PR`` query; the count is read when the reply arrives.
        lines_per_write: lines sent in one write while refilling.
        high_water, low_water: refill starts at ``lines_ahead <= low_water`` and stops at
            ``lines_ahead >= high_water`` (the manual's 1000 / 500).
        via_terminal: send ``&{cs}PR`` to the card's command line (on a port of the host's
            own) and read the count from its reply, as host software does; the reply comes at
            the end of a background cycle (``host_pr`` events record how long it took).
            Without it the count is read directly at the instant the query arrives (a
            stand-in with no command processing, e.g. a dual-ported-RAM status read).
        reply_timeout_s: with ``via_terminal``, how long the host waits for the reply before
            giving up on that poll (``host_timeout``).

    ``pr_latency`` is the link time to the card: the query reaches the card that much after
    the poll starts; the reply travels back at once ``[INF]`` (the manual gives no split).
    """

    def __init__(
        self,
        *args: Any,
        poll_period_s: float,
        pr_latency: Delay = _ZERO,
        lines_per_write: int = 1,
        high_water: int = 1000,
        low_water: int = 500,
        via_terminal: bool = False,
        **kwargs: Any,
    ) -> None:
        super().__init__(*args, **kwargs)
        if poll_period_s <= 0:
            raise ValueError("poll_period_s must be > 0")
        if not 0 <= low_water < high_water:
            raise ValueError("need 0 <= low_water < high_water")
        if lines_per_write < 1:
            raise ValueError("lines_per_write must be >= 1")
        self.poll_period_s = poll_period_s
        self.pr_latency = pr_latency
        self.lines_per_write = lines_per_write
        self.high_water = high_water
        self.low_water = low_water
        self.via_terminal = via_terminal
        self.replies: list[float] = []

    def ask_pr(self) -> Generator[Any, Any, int | None]:
        """``&cs PR`` on the card's command line; the count, or None (timeout or stopped)."""
        command = f"&{self.cs}PR"
        t_sent = self.env.now
        reply = yield from self.command(command)
        if reply is None:
            return None
        t_done = reply.t_done if reply.t_done is not None else self.env.now
        if reply.error:
            self._refused(command, t_done - t_sent, reply.error)
            return None
        ahead = int(float(reply.reply.split()[0])) if reply.reply.strip() else 0
        self.replies.append(t_done - t_sent)
        self.log.emit(
            "host_pr", host=self.name, cs=self.cs, lines_ahead=ahead, reply_s=t_done - t_sent
        )
        return ahead

    def _run(self) -> Generator[Any, Any, None]:
        env = self.env
        t0 = env.now
        k = 0
        while self.remaining > 0:
            delay = self.pr_latency.draw(self.rng)
            if delay > 0:
                yield env.timeout(delay)
            if self.via_terminal:
                ahead = yield from self.ask_pr()
                if self.stopped is not None:
                    return
            else:
                ahead = self.lines_ahead()
            if ahead is not None and ahead <= self.low_water:
                while self.remaining > 0 and ahead < self.high_water:
                    want = min(self.lines_per_write, self.high_water - ahead)
                    res = yield from self.write(want)
                    if res is None:
                        break
                    ahead = res.lines_ahead
                yield from self.start_program_once()
            # next poll on the host's own period grid (no drift from t += dt)
            k += 1
            nxt = t0 + k * self.poll_period_s
            while nxt <= env.now:
                k += 1
                nxt = t0 + k * self.poll_period_s
            yield env.timeout(nxt - env.now)


class BreqInterruptHost(PmacHost):
    """Services BREQ interrupts: after ``latency`` loads ``lines_per_interrupt`` lines.

    Args:
        latency: interrupt latency, BREQ edge to the service routine's first write.
        lines_per_interrupt: lines per write in the service routine.
        recheck_breq: keep loading while BREQ still reads high (until ``lines_ahead`` >= I17);
            without it the routine writes once and returns.
        prefill: lines loaded before the program starts (``None``: load until BREQ reads low).
    """

    def __init__(
        self,
        *args: Any,
        latency: Delay = _ZERO,
        lines_per_interrupt: int = 1,
        recheck_breq: bool = True,
        prefill: int | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(*args, **kwargs)
        if lines_per_interrupt < 1:
            raise ValueError("lines_per_interrupt must be >= 1")
        self.latency = latency
        self.lines_per_interrupt = lines_per_interrupt
        self.recheck_breq = recheck_breq
        self.prefill = prefill
        self.interrupts = 0
        self.missed = 0
        self._armed = False
        self._edge_t: float | None = None
        self._missed_at: list[float] = []
        self._wake = None

    def _on_event(self, ev: Any) -> None:
        if ev.type != "breq" or ev.fields.get("cs") != self.cs or not ev.fields.get("level"):
            return
        if self._armed:
            self._armed = False
            self._edge_t = ev.t
            if self._wake is not None and not self._wake.triggered:
                self._wake.succeed()
        else:
            self._missed_at.append(ev.t)

    def _flush_missed(self) -> None:
        """At the end of the service routine: an edge that came while interrupts were masked
        is lost if BREQ is still high now — no new edge will come to interrupt the host."""
        if self._missed_at and self.remaining > 0 and self._breq_high():
            t = self._missed_at[-1]
            self.missed += 1
            self.log.emit(
                "host_irq", host=self.name, cs=self.cs, missed=True, latency_s=self.env.now - t
            )
        self._missed_at.clear()

    def _breq_high(self) -> bool:
        rot = self.controller.rotary(self.cs)
        return bool(rot and rot["breq"])

    def _run(self) -> Generator[Any, Any, None]:
        env = self.env
        unlisten = self.log.listen(self._on_event)
        try:
            # Before the program runs: fill the buffer (to I17 when prefill is None).
            target = self.prefill
            while self.remaining > 0:
                n = self.lines_per_interrupt if target is None else min(
                    self.lines_per_interrupt, target - self.sent
                )
                if n <= 0:
                    break
                res = yield from self.write(n)
                if res is None or (target is None and not res.breq):
                    break
            yield from self.start_program_once()
            self._missed_at.clear()  # edges while pre-filling were not interrupts yet
            self._armed = True
            while self.remaining > 0:
                self._wake = env.event()
                yield self._wake
                edge_t = self._edge_t if self._edge_t is not None else env.now
                delay = self.latency.draw(self.rng)
                if delay > 0:
                    yield env.timeout(delay)
                self.interrupts += 1
                self.log.emit(
                    "host_irq",
                    host=self.name,
                    cs=self.cs,
                    missed=False,
                    latency_s=env.now - edge_t,
                )
                while self.remaining > 0:
                    res = yield from self.write(self.lines_per_interrupt)
                    if res is None or not self.recheck_breq or not res.breq:
                        break
                self._flush_missed()
                self._armed = True
        finally:
            unlisten()


class NaiveHost(PmacHost):
    """Sends ``lines_per_write`` lines per write back to back, as fast as the link allows.

    Only the write latency paces it; a full buffer makes it wait one more write time and retry.
    """

    def __init__(self, *args: Any, lines_per_write: int = 1, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        if lines_per_write < 1:
            raise ValueError("lines_per_write must be >= 1")
        self.lines_per_write = lines_per_write

    def _run(self) -> Generator[Any, Any, None]:
        env = self.env
        while self.remaining > 0:
            res = yield from self.write(self.lines_per_write)
            yield from self.start_program_once()
            if res is None:
                delay = self.write_latency.draw(self.rng)
                # a zero-latency link still has to wait for the card to make room
                yield env.timeout(delay if delay > 0 else 1e-4)


__all__ = [
    "WRITE_VIA",
    "BreqInterruptHost",
    "NaiveHost",
    "PmacHost",
    "PrPollingHost",
    "WriteResult",
]
