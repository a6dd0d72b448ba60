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
    counting, the rest is collected later."""
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
            if _pauses == 0 and _state.get("enabled", True):
                gc.enable()


def without_gc(fn: Callable[[T_in], T], arg: T_in) -> T:
    """``fn(arg)`` inside :func:`gc_paused`."""
    with gc_paused():
        return fn(arg)


__all__ = ["INLINE_BYTES", "WORKER", "gc_paused", "off_loop", "without_gc"]
