"""Rotary-buffer batches parsed in slices, so a large batch never holds the event loop.

Parsing a program line costs from microseconds (``X1``) to milliseconds (a 255-character line
of expressions); a batch of thousands of them parsed in one go would stop ``/health``, the
TCP ports and every other client for seconds. :func:`precompile` parses the batch's distinct
texts here, at most ``SLICE_S`` of wall time at a stretch with the event loop served in
between (the clock's own slicing, :mod:`motionsim.app.clock`); the route then hands the
compiled lines to the controller's ``load_lines``, which stores the batch in one
step at the current instant, all or nothing as before, and only looks its lines up. A line
that does not parse is left to the controller, which reports it with its ``index`` as before.

Lines per batch are bounded (``MAX_BATCH_LINES``, 422 naming ``lines`` with the limit).
"""

from __future__ import annotations

import contextlib
import time
from typing import Any

from ..app.clock import SLICE_S, loop_turns
from ..sim.errors import MotionSimError
from ..sim.pmac import MAX_LINE_CHARS, PmacController, ProgramLine, compile_line
from .off_loop import gc_paused

#: Most lines in one ``POST .../rotary/lines`` batch [INF: no manual limit; a host streams in
#: batches, and storing one is a single step on the loop (all or nothing): 1 024 lines take
#: tens of milliseconds, 4 096 a few hundred].
MAX_BATCH_LINES = 1024


async def precompile(texts: list[Any]) -> dict[str, ProgramLine]:
    """The compiled form of each distinct text the controller has not at hand, parsed in
    slices."""
    known = PmacController.line_compiled
    out: dict[str, ProgramLine] = {}
    end = time.monotonic() + SLICE_S
    # A full collection triggered by the objects parsing creates would hold the loop for
    # longer than many slices (its cost grows with the heap): paused while this batch parses.
    with gc_paused():
        for text in dict.fromkeys(t for t in texts if type(t) is str):
            if text in out or len(text) > MAX_LINE_CHARS or known(text):
                continue
            with contextlib.suppress(MotionSimError):  # the controller reports it, positioned
                out[text] = compile_line(text)
            if time.monotonic() > end:
                await loop_turns()
                end = time.monotonic() + SLICE_S
    return out


__all__ = ["MAX_BATCH_LINES", "precompile"]
