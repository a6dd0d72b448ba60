"""Errors the process must not survive: it exits so that a supervisor restarts it.

A ``MemoryError`` leaves a Python process alive but unreliable (any allocation may fail next,
half-finished updates may be left behind): a service that answers ``/health`` "ok" in that state
is worse than one that is gone. :func:`exit_if_fatal` is called wherever the service catches
"any exception" to keep going (the 500 handler, the TCP connection loop, the event loop's
handler for exceptions nobody awaited) and ends the process at once with :data:`EXIT_MEMORY`.
"""

from __future__ import annotations

import asyncio
import os
import sys
from typing import Any

#: The exit status after a MemoryError (``motionsim serve``'s other failures exit 1 or 2).
EXIT_MEMORY = 3


def exit_if_fatal(exc: BaseException | None) -> None:
    """End the process now if ``exc`` is one it must not survive (a ``MemoryError``)."""
    if isinstance(exc, MemoryError):
        try:
            sys.stderr.write("motionsim: out of memory (MemoryError); exiting so that a "
                             "supervisor can restart the service\n")
            sys.stderr.flush()
        finally:
            os._exit(EXIT_MEMORY)


def install_loop_handler(loop: asyncio.AbstractEventLoop) -> None:
    """Exit on a fatal exception the event loop reports (a task nobody awaited)."""
    previous = loop.get_exception_handler()

    def handler(loop: asyncio.AbstractEventLoop, context: dict[str, Any]) -> None:
        exit_if_fatal(context.get("exception"))
        if previous is not None:
            previous(loop, context)
        else:
            loop.default_exception_handler(context)

    loop.set_exception_handler(handler)


__all__ = ["EXIT_MEMORY", "exit_if_fatal", "install_loop_handler"]
