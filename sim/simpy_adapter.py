"""The one place motionsim touches SimPy's internals: events queued at an absolute instant.

Both controllers act on servo interrupts whose instants are computed from integer cycle
indices (``k * period``). SimPy only offers relative delays, and ``now + (t - now)`` can miss
``t`` by a rounding step, so such events go on the environment's queue at ``t`` itself, as
``Environment.schedule`` does internally. That needs SimPy 4's queue layout (``_queue`` a heap
of ``(t, priority, eid, event)``, ``_eid`` the tie-break counter); a SimPy upgrade that changes
it breaks this module only (``tests/sim/test_simpy_adapter.py`` pins what the rest relies on).
"""

from __future__ import annotations

from collections.abc import Callable
from heapq import heappush
from typing import Any

import simpy
from simpy.events import NORMAL, URGENT, EventPriority

__all__ = [
    "NORMAL", "URGENT", "Due", "UrgentWake", "Wake", "cancel", "clear_pre_step", "next_eid",
    "nothing_due_by", "pending", "pre_step", "push_at", "set_now", "step_due", "succeed_at",
    "supersede", "triggered_at", "urgent_at", "wake_at",
]  # fmt: skip

Callback = Callable[[Any], None]


def push_at(env: simpy.Environment, t: float, event: simpy.events.Event,
            priority: EventPriority = NORMAL) -> None:
    """Put an already-triggered ``event`` on ``env``'s queue, processed at the instant ``t``;
    ``URGENT`` ones before ``NORMAL`` ones at the same instant, each in the order pushed."""
    heappush(env._queue, (t, priority, next(env._eid), event))


class Wake(simpy.events.Event):
    """An already-triggered event processed at the absolute instant ``t``, calling ``fn``.

    Like ``env.timeout(t - now)`` but cheaper and exact (see the module docstring).
    """

    # Triggered and successful from birth (class-level, saving two stores per wake-up).
    _value = None
    _ok = True

    def __init__(self, env: simpy.Environment, t: float, fn: Callback) -> None:
        self.env = env
        self.callbacks = [fn]
        heappush(env._queue, (t, NORMAL, next(env._eid), self))


def wake_at(env: simpy.Environment, t: float, fn: Callback, old: Wake | None = None) -> Wake:
    """Call ``fn(event)`` at the absolute instant ``t``: a :class:`Wake`.

    ``old`` is a wake-up of the caller's that may be re-used: once SimPy has processed it
    (``callbacks is None``) nothing else refers to it, so it is put on the queue again instead
    of allocating a new event — one allocation less per move on the streaming path. Cancelled
    wake-ups (callbacks emptied, still queued) are never re-used. The queue entry is the same
    as a new Wake's (same ``eid`` order), so the schedule is unchanged.
    """
    if old is not None and old.callbacks is None:
        old.callbacks = [fn]
        heappush(env._queue, (t, NORMAL, next(env._eid), old))
        return old
    return Wake(env, t, fn)


def cancel(event: simpy.events.Event | None) -> None:
    """Cancel a wake-up that has not happened yet: it stays on the queue (SimPy has no
    removal) and is processed at its instant as a no-op, calling nothing. ``None``, an event
    already processed or one already cancelled: nothing to do. A cancelled :class:`Wake` is
    never re-used by :func:`wake_at` (it is still queued)."""
    if event is not None and event.callbacks:
        event.callbacks.clear()


def supersede(env: simpy.Environment, t: float, fn: Callback, old: Wake | None) -> Wake:
    """Call ``fn(event)`` at ``t`` *instead of* what ``old`` was to do: ``old`` is cancelled if
    still queued (:func:`cancel`), or re-used if already processed (:func:`wake_at`). One call
    for the pattern "the one pending wake-up of this thing moves" (a CS's next execution
    step, once per streamed line)."""
    if old is not None:
        cbs = old.callbacks
        if cbs is None:  # processed: nothing refers to it, re-used
            old.callbacks = [fn]
            heappush(env._queue, (t, NORMAL, next(env._eid), old))
            return old
        cbs.clear()  # still queued: cancelled (a no-op when it already was)
    return Wake(env, t, fn)


def pending(event: simpy.events.Event | None) -> bool:
    """``event`` is queued and will still call something (not processed, not cancelled)."""
    return event is not None and bool(event.callbacks)


def nothing_due_by(env: simpy.Environment, t: float) -> bool:
    """No event is queued at or before the instant ``t``: an event pushed now at ``t`` would be
    the next one ``env`` processes (whatever its priority), unless another is pushed first."""
    queue = env._queue
    return not queue or queue[0][0] > t


def step_due(env: simpy.Environment, limit: float, n: int) -> int:
    """Process the events due at or before the instant ``limit``, oldest first, at most ``n``
    of them; return how many were processed (fewer than ``n``: nothing more is due by
    ``limit``). ``while env.peek() <= limit: env.step()`` without a method call per look:
    the loop a virtual clock's slice runs, once per event. ``env.step`` is looked up for each
    event, so a :func:`pre_step` hook installed or cleared by an event takes effect at once."""
    queue = env._queue
    k = 0
    while k < n and queue and queue[0][0] <= limit:
        env.step()
        k += 1
    return k


def triggered_at(env: simpy.Environment, t: float, fn: Callback,
                 priority: EventPriority = URGENT) -> simpy.events.Event:
    """A plain SimPy event, already succeeded, that calls ``fn`` at the instant ``t``
    (``URGENT`` by default: before normal events at ``t``)."""
    ev = simpy.Event(env)
    ev._ok = True
    ev._value = None
    ev.callbacks.append(fn)
    push_at(env, t, ev, priority)
    return ev


#: ``fn(t, priority, eid)`` of :func:`pre_step`: the queue key of the event about to be processed.
PreStep = Callable[[float, int, int], None]


def next_eid(env: simpy.Environment) -> int:
    """Take the next tie-break number of ``env``'s queue, as scheduling an event would: a
    virtual event "pushed now" orders after everything already queued and before everything
    pushed later, at the same instant and priority."""
    return next(env._eid)


def pre_step(env: simpy.Environment, fn: PreStep) -> None:
    """Call ``fn(t, priority, eid)`` with the queue key of the next event before each event
    ``env`` processes (nothing when the queue is empty), until :func:`clear_pre_step`.

    This lets a task that would otherwise wake on every servo cycle keep its wake-ups virtual:
    before anything else happens it does the work of the wake-ups that would have come first
    (their keys compare with the event's the way the queue orders them). ``env.step`` is
    replaced on the instance (``Environment.run`` and every driver call it), so nothing is
    paid while no hook is installed; one hook per environment.
    """
    original = type(env).step
    queue = env._queue

    def step() -> None:
        if queue:
            t, priority, eid, _ = queue[0]
            fn(t, priority, eid)
        original(env)

    env.step = step  # type: ignore[method-assign]


def set_now(env: simpy.Environment, t: float) -> None:
    """Move ``env``'s clock to ``t`` inside a :func:`pre_step` hook, for the work of a virtual
    wake-up at ``t`` (at or after the last event's instant, at or before the next one's,
    which the step then sets anyway)."""
    env._now = t


def clear_pre_step(env: simpy.Environment) -> None:
    """Remove the :func:`pre_step` hook (none installed: nothing to do)."""
    env.__dict__.pop("step", None)


class UrgentWake(simpy.events.Event):
    """An already-triggered ``URGENT`` event processed at the absolute instant ``t``, calling
    ``fn(event)``: what :func:`triggered_at` does with its default priority, in one
    allocation and no call beyond it (the Trio servo interrupt, once per servo period that
    does something). :func:`urgent_at` is this class."""

    _value = None
    _ok = True
    #: What the caller attached for its callback to read (the Trio servo period's index).
    k: int

    def __init__(self, env: simpy.Environment, t: float, fn: Callback) -> None:
        self.env = env
        self.callbacks = [fn]
        heappush(env._queue, (t, URGENT, next(env._eid), self))


#: ``urgent_at(env, t, fn)``: call ``fn(event)`` at the instant ``t`` with ``URGENT`` priority
#: (an :class:`UrgentWake`, the class itself: constructing it queues it).
urgent_at = UrgentWake


class Due(simpy.events.Event):
    """An already-triggered event processed at the absolute instant ``t``, for a process to
    yield: ``env.timeout(t - now)`` in one call (same queue entry: ``NORMAL``, next ``eid``)."""

    _value = None
    _ok = True

    def __init__(self, env: simpy.Environment, t: float) -> None:
        self.env = env
        self.callbacks = []
        heappush(env._queue, (t, NORMAL, next(env._eid), self))


def succeed_at(env: simpy.Environment, event: simpy.events.Event, t: float) -> None:
    """Trigger the pending ``event`` (value None) so that it is processed at the instant ``t``
    (``NORMAL``): what its ``succeed()`` does for the present instant."""
    event._ok = True
    event._value = None
    heappush(env._queue, (t, NORMAL, next(env._eid), event))
