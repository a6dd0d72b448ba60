"""The calls that wait on one controller's simulation, so that deleting it ends them.

``advance``, ``run-until``, a terminal command waiting for its reply and a ``?wait=true`` move
run the simulation (or wait for it) for as long as their arguments ask — days of simulated
time for ``advance 1e6``. Each runs as a task registered in the controller's :class:`InFlight`;
``DELETE /controllers/{id}`` cancels every one at its next slice boundary, and the caller gets
:class:`ControllerDeleted` (410 ``controller_deleted``) at once: nothing goes on simulating a
controller that no longer exists, and no call answers 200 about it afterwards.
"""

from __future__ import annotations

import asyncio
from collections.abc import Awaitable, Generator
from typing import TypeVar

from ..sim.errors import MotionSimError
from .clock import drain_async

T = TypeVar("T")


class ControllerDeleted(MotionSimError):
    """The controller was deleted while the call waited on it (410)."""

    code = "controller_deleted"


class InFlight:
    """The waiting calls of one controller (``id`` names it in the error)."""

    def __init__(self, id: str) -> None:
        self.id = id
        self.closed = False
        self._tasks: set[asyncio.Task[object]] = set()

    def __len__(self) -> int:
        return len(self._tasks)

    def _deleted(self) -> ControllerDeleted:
        return ControllerDeleted(f"controller {self.id!r} was deleted; the call was cancelled",
                                 controller=self.id)

    async def run(self, work: Awaitable[T]) -> T:
        """Await ``work`` as a task :meth:`close` can cancel.

        Raises:
            ControllerDeleted: the controller is (or gets) deleted before ``work`` ends.
            asyncio.CancelledError: the caller itself was cancelled (its client went away).
        """
        if self.closed:
            if asyncio.iscoroutine(work):
                work.close()
            raise self._deleted()
        task: asyncio.Task[T] = asyncio.ensure_future(work)
        self._tasks.add(task)  # type: ignore[arg-type]
        try:
            return await task
        except asyncio.CancelledError:
            current = asyncio.current_task()
            if self.closed and (current is None or not current.cancelling()):
                raise self._deleted() from None
            raise
        finally:
            self._tasks.discard(task)  # type: ignore[arg-type]

    async def run_sliced(self, steps: Generator[None, None, T]) -> T:
        """:func:`~motionsim.app.clock.drain_async` of ``steps`` as :meth:`run` awaits it,
        with its first slice run at once: a computation that ends within its first slice (a
        terminal reply the next background cycle gives, the usual case) needs no task and no
        turn of the event loop; one that goes on continues as a task :meth:`close` can cancel,
        after the turns the loop gets between any two slices. Nothing can cancel a slice
        while it runs, so deleting the controller ends the call at the same slice boundary.

        Raises:
            ControllerDeleted: as :meth:`run`.
        """
        if self.closed:
            steps.close()
            raise self._deleted()
        try:
            next(steps)
        except StopIteration as stop:
            return stop.value  # type: ignore[no-any-return]
        return await self.run(drain_async(steps, started=True))

    async def close(self) -> None:
        """The controller is deleted: cancel every waiting call and let each one stop."""
        self.closed = True
        tasks = list(self._tasks)
        for task in tasks:
            task.cancel()
        if tasks:
            await asyncio.wait(tasks)


__all__ = ["ControllerDeleted", "InFlight"]
