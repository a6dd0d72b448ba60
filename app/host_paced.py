"""The host-paced clock: virtual time for hosts that run outside the test's control flow.

A host under test (a streamer in another thread or process) reacts to what the controller does:
BREQ going high, a ``run-until`` event, a Trio process blocking on a move. On a virtual clock
the test moves time and the host's reaction lands wherever wall timing puts it; on a realtime
clock the run takes wall time. Here the simulation runs as fast as the CPU allows but *holds*
for the clients taking part, its **holders**:

- a holder is *acting* (time stands still for it) or *waiting* for an event pattern and/or a
  simulated deadline (``run-until``, ``advance``);
- time moves only while every holder waits, up to the earliest instant one of them is due:
  its deadline, or the instant of its matching event plus the clock's ``reaction_s`` (the
  host's reaction time, in simulated seconds: what happens in that time still happens);
- there the holder becomes *acting* again and its call returns; what it then does lands at that
  instant, however long it takes in wall time, until it waits again or is released.

So the event log depends only on what the holders do, not on when the operating system runs
them: the same host gives the same log, byte for byte, and 60 simulated seconds take only the
CPU time they need. A holder registered before it first waits (``PUT .../clock/holders/{name}``,
``holders`` in the PATCH) keeps time still until its host is ready. Requests from clients that
are not holders land at the instant the clock has reached.

A call waiting longer than its wall cap (a holder that never acts again: a crashed host)
returns unmatched with the names of the holders time is held by.
"""

from __future__ import annotations

import asyncio
import logging
import re
import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Literal

import simpy

from ..sim.errors import Conflict, InvalidValue
from ..sim.events import Event, EventLog
from .clock import (
    _INF,
    _WALL_CHECK_STEPS,
    RUN_UNTIL_WALL_S,
    SLICE_S,
    ClockMode,
    DrivenClock,
    _check_seconds,
    _limit,
    loop_turns,
    run_env_to,
)

log = logging.getLogger("motionsim.clock")

#: The holder a request names when it names none.
DEFAULT_HOLDER = "main"

#: Most simulated seconds a host's reaction may take.
MAX_REACTION_S = 60.0

#: Most holders one clock keeps.
MAX_HOLDERS = 64

_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,63}$")

HolderState = Literal["acting", "waiting"]


def check_reaction(value: float) -> float:
    """A host reaction time: finite, 0 .. ``MAX_REACTION_S`` simulated seconds."""
    value = _check_seconds(value, "reaction_s")
    if value > MAX_REACTION_S:
        raise InvalidValue(f"reaction_s must be <= {MAX_REACTION_S:g}, got {value!r}",
                           field="reaction_s")
    return value


def check_holder(name: str) -> str:
    if not isinstance(name, str) or not _NAME.match(name):
        raise InvalidValue(f"holder {name!r} must be 1-64 letters, digits, '_', '.', '-'",
                           field="holder")
    return name


@dataclass(slots=True)
class Holder:
    """One client taking part in pacing (see the module docstring)."""

    name: str
    state: HolderState
    since_t: float
    pattern: dict[str, Any] | None = None
    deadline: float = _INF
    due: float | None = None  # its pattern matched: the instant it becomes acting
    matched: Event | None = None
    result: asyncio.Future[tuple[Event | None, str]] | None = field(default=None, repr=False)

    def to_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {"name": self.name, "state": self.state, "since_t": self.since_t}
        if self.state == "waiting":
            out["event"] = self.pattern
            out["until_t"] = None if self.deadline == _INF else self.deadline
        return out


class HostPacedClock(DrivenClock):
    """Time moves while every holder waits; it holds where one is due (module docstring).

    Args:
        reaction_s: simulated seconds between a holder's event and the instant it acts.
        log: the controller's event log (holders wait for its events).
        slice_s: wall seconds per slice of simulation before the loop gets a turn.
    """

    mode: ClockMode = "host-paced"

    def __init__(self, env: simpy.Environment, factor: float = 1.0, paused: bool = False, *,
                 log: EventLog | None = None, reaction_s: float = 0.0,
                 slice_s: float = SLICE_S) -> None:
        super().__init__(env, factor, paused)
        if log is None:
            raise InvalidValue("a host-paced clock needs the controller's event log",
                               field="log")
        self.log = log
        self.reaction_s = check_reaction(reaction_s)
        self.slice_s = slice_s
        self.holders: dict[str, Holder] = {}
        #: Holders released and not registered again: their calls return ``released`` at once
        #: (a host that is told to stop must not take time hostage again by waiting).
        self.released: set[str] = set()
        self._target: float | None = None  # cached earliest due instant; None = recompute
        self._wakeup: asyncio.Event | None = None
        self._unlisten = log.listen(self._on_event)
        self.last_error: BaseException | None = None

    # -- holders -----------------------------------------------------------------------------

    def hold(self, name: str) -> Holder:
        """Register holder ``name``, acting at the current instant (no change if known)."""
        self.released.discard(check_holder(name))
        holder = self.holders.get(name)
        if holder is None:
            if len(self.holders) >= MAX_HOLDERS:
                raise Conflict(f"a clock keeps at most {MAX_HOLDERS} holders")
            holder = self.holders[name] = Holder(name, "acting", self.env.now)
        return holder

    def release(self, name: str) -> bool:
        """Forget holder ``name`` (a call it is waiting in returns ``released``)."""
        holder = self.holders.pop(name, None)
        self.released.add(name)
        if holder is None:
            return False
        self._resolve(holder, None, "released")
        self._changed()
        return True

    def release_all(self) -> None:
        for name in list(self.holders):
            self.release(name)
        self.released.clear()

    def held_by(self) -> list[str]:
        """The holders time stands still for."""
        return [h.name for h in self.holders.values() if h.state == "acting"]

    async def wait(self, name: str, pattern: Mapping[str, Any] | None, timeout_s: float, *,
                   wall_timeout_s: float = RUN_UNTIL_WALL_S) -> tuple[Event | None, str]:
        """Holder ``name`` waits for ``pattern`` (None: only the deadline), at most
        ``timeout_s`` simulated seconds; returns ``(matched event or None, outcome)`` once it is
        acting again. Outcome: ``matched``, ``timeout`` (simulated), ``released``, or
        ``wall_timeout`` (other holders kept time still for ``wall_timeout_s`` wall seconds).
        """
        timeout_s = _check_seconds(timeout_s, "timeout_s")
        if self.paused:
            raise Conflict("the clock is paused; PATCH it with paused=false first")
        if check_holder(name) in self.released:
            return None, "released"
        holder = self.hold(name)
        if holder.state == "waiting":
            raise Conflict(f"holder {name!r} is already waiting (one call per holder at a time)")
        loop = asyncio.get_running_loop()
        holder.state = "waiting"
        holder.since_t = self.env.now
        holder.pattern = None if pattern is None else dict(pattern)
        holder.deadline = self.env.now + timeout_s
        holder.due = None
        holder.matched = None
        result = holder.result = loop.create_future()
        self._changed()
        try:
            return await asyncio.wait_for(asyncio.shield(result), timeout=wall_timeout_s)
        except TimeoutError:
            self._resolve(holder, None, "wall_timeout")
            return None, "wall_timeout"
        except asyncio.CancelledError:
            # The client went away: it acts no more, so it no longer holds time either.
            self.release(name)
            raise

    def _resolve(self, holder: Holder, event: Event | None, outcome: str) -> None:
        """The holder is acting again from now; its waiting call gets its answer."""
        holder.state = "acting"
        holder.since_t = self.env.now
        holder.pattern = None
        holder.deadline = _INF
        holder.due = None
        holder.matched = None
        result, holder.result = holder.result, None
        if result is not None and not result.done():
            result.set_result((event, outcome))
        self._target = None

    def _on_event(self, event: Event) -> None:
        """A holder waiting for this event is due ``reaction_s`` after it."""
        for holder in self.holders.values():
            if (holder.state == "waiting" and holder.due is None and holder.pattern is not None
                    and event.matches(holder.pattern)):
                holder.due = event.t + self.reaction_s
                holder.matched = event
                self._target = None

    def _due_at(self) -> float:
        """The earliest instant a waiting holder is due (inf when none can be)."""
        if self._target is None:
            due = _INF
            for h in self.holders.values():
                if h.state == "waiting":
                    due = min(due, h.deadline if h.due is None else min(h.due, h.deadline))
            self._target = due
        return self._target

    def _runnable(self) -> bool:
        holders = self.holders.values()
        return (not self.paused and bool(self.holders)
                and all(h.state == "waiting" for h in holders))

    def _changed(self) -> None:
        self._target = None
        self.wake()

    # -- Clock -------------------------------------------------------------------------------

    def set(self, *, factor: float | None = None, paused: bool | None = None,
            reaction_s: float | None = None) -> None:
        if reaction_s is not None:
            self.reaction_s = check_reaction(reaction_s)
        super().set(factor=factor, paused=paused)
        self._changed()

    def wake(self) -> None:
        if self._wakeup is not None:
            self._wakeup.set()

    def start(self) -> None:
        if self.running:
            return
        self._wakeup = asyncio.Event()
        self._start_task("host-paced-clock")

    async def stop(self) -> None:
        self.release_all()
        await super().stop()

    def close(self) -> None:
        """Stop listening to the log (the clock is replaced or the controller deleted)."""
        self._unlisten()

    def to_dict(self) -> dict[str, Any]:
        out = super().to_dict()
        out["reaction_s"] = self.reaction_s
        out["holders"] = [h.to_dict() for h in self.holders.values()]
        out["held_by"] = self.held_by()
        return out

    # -- the driving task --------------------------------------------------------------------

    def _run_slice(self) -> bool:
        """Step towards the earliest due instant for one slice; True when it was reached."""
        env = self.env
        slice_end = time.monotonic() + self.slice_s
        steps = 0
        while True:
            target = self._due_at()
            if env.peek() > _limit(target):
                if target != _INF and target > env.now:
                    run_env_to(env, target)
                return target != _INF or env.peek() == _INF
            env.step()
            steps += 1
            if steps % _WALL_CHECK_STEPS == 0 and time.monotonic() > slice_end:
                return False

    def _deliver(self) -> None:
        """The first waiting holder due by now becomes acting; its call returns.

        Holders due at the same instant act one at a time, in an order that does not depend on
        thread scheduling: the one due earliest, then the one waiting since the earliest
        simulated instant, then by name. The next one's call returns once this one waits again
        (or is released), at the same simulated instant."""
        limit = _limit(self.env.now)
        due = []
        for holder in self.holders.values():
            if holder.state != "waiting":
                continue
            if holder.due is not None and holder.due <= limit:
                due.append((holder.due, holder.since_t, holder.name, holder, "matched"))
            elif holder.deadline <= limit:
                due.append((holder.deadline, holder.since_t, holder.name, holder, "timeout"))
        if due:
            *_, holder, outcome = min(due, key=lambda d: d[:3])
            self._resolve(holder, holder.matched if outcome == "matched" else None, outcome)

    async def _drive(self) -> None:
        wakeup = self._wakeup
        assert wakeup is not None
        while True:
            if not self._runnable():
                wakeup.clear()
                await wakeup.wait()
                continue
            try:
                reached = self._run_slice()
            except Exception as exc:  # a failed SimPy process: report it, hand control back
                self.last_error = exc
                log.exception("simulation error in host-paced clock")
                reached = True
            if reached:
                self._deliver()
                if self._runnable() and self._due_at() == _INF and self.env.peek() == _INF:
                    # Nothing scheduled and nobody due: idle until a holder or command acts.
                    wakeup.clear()
                    await wakeup.wait()
                    continue
            await loop_turns()


__all__ = ["DEFAULT_HOLDER", "MAX_REACTION_S", "Holder", "HostPacedClock", "check_holder",
           "check_reaction"]
