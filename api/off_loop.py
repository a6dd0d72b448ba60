"""CPU-bound parsing kept off the event loop: one worker thread shared by every request.

Compiling a large program text (a Trio BASIC program, a PLC) is pure work of seconds — a
function of the text alone — while storing the result is a moment's mutation. The compile
runs here, in one worker thread at a time (a request waits its turn, so many large uploads
never leave the loop competing with many threads for the interpreter); the caller then stores
the compiled form on the loop at the current simulated instant. Small texts are compiled
inline: a thread hand-off would cost more than the work. A compile error is raised to the
caller unchanged (422 ``parse_error``, line and column), and nothing is stored.
"""

from __future__ import annotations

import contextlib
import gc
import threading
from collections.abc import Callable, Iterator
from typing import TypeVar

import anyio
import anyio.to_thread

T = TypeVar("T")
T_in = TypeVar("T_in")

#: Texts up to this size are compiled on the loop (well under a slice).
INLINE_BYTES = 4 * 1024

#: The one worker thread (shared with the body guard's JSON check of large bodies).
WORKER = anyio.CapacityLimiter(1)

#: Objects left to the collector's young generation by a pause, above which they are frozen
#: when it ends (:func:`gc_paused`): one pass over this many takes about a millisecond.
FREEZE_AT = 20_000


async def off_loop(fn: Callable[[str], T], text: str) -> T:
    """``fn(text)``, in the worker thread when ``text`` is large."""
    if len(text) <= INLINE_BYTES:
        return fn(text)
    return await anyio.to_thread.run_sync(without_gc, fn, text, limiter=WORKER)


_pauses = 0
_pause_lock = threading.Lock()
_state: dict[str, bool] = {}  # "enabled": whether the collector ran before the first pause


@contextlib.contextmanager
def gc_paused() -> Iterator[None]:
    """The cyclic garbage collector paused while inside (nested and concurrent uses counted:
    it runs again when the last one ends). A full collection triggered by the objects a large
    parse creates would hold the interpreter lock, hence the event loop, for hundreds of
    milliseconds (its cost grows with the heap); what the parse drops is freed by reference
    counting, the rest is collected later.

    When the last pause ends with more than ``FREEZE_AT`` new objects still alive (a compiled
    program, a batch of compiled lines: hundreds of thousands of them), they are frozen
    (``gc.freeze``) rather than left to the collector: its next young pass would walk them
    all in one go (30 ms per 400 000), the pass after that again, and every full pass from
    then on. Compiled forms hold no reference cycles, so they are still freed, by reference
    counting, when replaced or deleted; only cyclic garbage waiting for the collector at
    that moment is kept [INF: a few hundred objects per large upload at most]."""
    global _pauses
    with _pause_lock:
        _pauses += 1
        if _pauses == 1:
            was_enabled = gc.isenabled()
            gc.disable()
            _state["enabled"] = was_enabled
    try:
        yield
    finally:
        with _pause_lock:
            _pauses -= 1
            if _pauses == 0:
                if gc.get_count()[0] > FREEZE_AT:
                    gc.freeze()
                if _state.get("enabled", True):
                    gc.enable()


def without_gc(fn: Callable[[T_in], T], arg: T_in) -> T:
    """``fn(arg)`` inside :func:`gc_paused`."""
    with gc_paused():
        return fn(arg)


__all__ = ["FREEZE_AT", "INLINE_BYTES", "WORKER", "gc_paused", "off_loop", "without_gc"]
