"""Host programs that feed moves to a Trio Motion Coordinator's axes.

A Trio axis holds the move executing now (MTYPE) and one next move (NTYPE); a third move from
the same process waits in that process's single process buffer, and a fourth blocks the
process — on the command line the terminal locks (TN20-16). A host that feeds several axes in
turn can therefore stall an axis that has room while it waits on another. Three feeders:

* :class:`BlindFeeder` — issues the moves in program order and waits whenever a move cannot be
  buffered (the TN20 stall).
* :class:`NtypeFeeder` — before each move tests ``NTYPE AXIS(n)=0`` and issues only to axes
  with a free NTYPE, skipping the others this pass (the TN20 fix); it never blocks.
* :class:`MovesBufferedFeeder` — in program order, waits until the axis's ``MOVES_BUFFERED``
  (moves held in MTYPE + NTYPE) is below ``max_buffered`` before issuing.

They call only ``move(axis, type, args, process=..., wait=...)`` and ``axis(n)``. A host
waiting for room adds ``host_blocked`` (``host``, ``axis``, ``process``) and ``host_resumed``
(same fields) events to the log, so a run's metrics can tell the axes that idled while it waited;
``host_done`` (``host``, ``moves``) marks the end.
"""

from __future__ import annotations

from collections.abc import Generator, Sequence
from dataclasses import dataclass
from typing import Any

from ..errors import BufferFull


@dataclass(frozen=True, slots=True)
class Move:
    """One move command: ``MOVE(10) AXIS(0)`` is ``Move(0, "MOVE", (10.0,))``."""

    axis: int
    type: str
    args: tuple[float, ...]


def interleave(per_axis: dict[int, Sequence[float]], type_: str = "MOVE") -> list[Move]:
    """Moves in the order of TN20's loop: move n of every axis, then move n+1, ..."""
    axes = sorted(per_axis)
    longest = max((len(v) for v in per_axis.values()), default=0)
    out: list[Move] = []
    for i in range(longest):
        for a in axes:
            if i < len(per_axis[a]):
                out.append(Move(a, type_, (float(per_axis[a][i]),)))
    return out


def moves_buffered(axis_state: dict[str, Any]) -> int:
    """``MOVES_BUFFERED``: moves held on the axis (MTYPE and NTYPE slots in use)."""
    if "moves_buffered" in axis_state:
        return int(axis_state["moves_buffered"])
    return int(axis_state.get("mtype", 0) != 0) + int(axis_state.get("ntype", 0) != 0)


class TrioFeeder:
    """Common part of the feeders.

    Args:
        name: the host's name in ``host_*`` events.
        controller: a Trio controller (``move``, ``axis``, ``env``, ``log``).
        moves: the moves to issue, in program order.
        process: the process the moves are issued as (``None``: the command line, process 0).
        poll_period_s: how often a polling feeder looks again.
    """

    def __init__(
        self,
        name: str,
        controller: Any,
        moves: Sequence[Move],
        *,
        process: int | None = None,
        poll_period_s: float = 0.001,
    ) -> None:
        if poll_period_s <= 0:
            raise ValueError("poll_period_s must be > 0")
        self.name = name
        self.controller = controller
        self.env = controller.env
        self.log = controller.log
        self.moves = list(moves)
        self.process_no = process
        self.poll_period_s = poll_period_s
        self.issued = 0
        self.done_t: float | None = None
        self.process = None
        self.stall_until = 0.0

    def stall(self, until_s: float) -> None:
        """Fault: the host does nothing until ``until_s``."""
        self.stall_until = max(self.stall_until, until_s)

    def wait_if_stalled(self) -> Generator[Any, Any, None]:
        if self.env.now < self.stall_until:
            yield self.env.timeout(self.stall_until - self.env.now)

    def start(self) -> None:
        self.process = self.env.process(self._run())

    def _run(self) -> Generator[Any, Any, None]:  # pragma: no cover - overridden
        raise NotImplementedError
        yield

    def try_move(self, move: Move) -> bool:
        """Issue ``move`` now; ``False`` if all three buffers are full (nothing queued)."""
        try:
            self.controller.move(move.axis, move.type, list(move.args), process=self.process_no)
        except BufferFull:
            return False
        self.issued += 1
        return True

    def place_blocking(self, move: Move) -> Generator[Any, Any, None]:
        """Issue ``move``, waiting (blocked) until the controller has room for it.

        The controller queues a move that does not fit like a BASIC move line
        (``move(..., wait=True)``) and answers when it is buffered.
        """
        yield from self.wait_if_stalled()
        if self.try_move(move):
            return
        fields = {"host": self.name, "axis": move.axis, "process": self.process_no or 0}
        self.log.emit("host_blocked", **fields)
        reply = self.controller.move(
            move.axis, move.type, list(move.args), process=self.process_no, wait=True
        )
        done = self.env.event()
        reply.add_done_callback(lambda _r: done.triggered or done.succeed())
        yield done
        self.issued += 1
        self.log.emit("host_resumed", **fields)

    def finish(self) -> None:
        self.done_t = self.env.now
        self.log.emit("host_done", host=self.name, moves=self.issued)


class BlindFeeder(TrioFeeder):
    """Issues every move in order, blocking on a full axis like a BASIC move line."""

    def _run(self) -> Generator[Any, Any, None]:
        for move in self.moves:
            yield from self.place_blocking(move)
        self.finish()


class NtypeFeeder(TrioFeeder):
    """Each pass, issues the next move of every axis whose NTYPE is 0 (TN20's fix)."""

    def _run(self) -> Generator[Any, Any, None]:
        queues: dict[int, list[Move]] = {}
        for m in self.moves:
            queues.setdefault(m.axis, []).append(m)
        heads = dict.fromkeys(queues, 0)
        while any(heads[a] < len(q) for a, q in queues.items()):
            yield from self.wait_if_stalled()
            for a in sorted(queues):
                free = heads[a] < len(queues[a]) and self.controller.axis(a)["ntype"] == 0
                if free and self.try_move(queues[a][heads[a]]):
                    heads[a] += 1
            yield self.env.timeout(self.poll_period_s)
        self.finish()


class MovesBufferedFeeder(TrioFeeder):
    """In program order, waits until ``MOVES_BUFFERED`` of the axis < ``max_buffered``."""

    def __init__(self, *args: Any, max_buffered: int = 2, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        if max_buffered < 1:
            raise ValueError("max_buffered must be >= 1")
        self.max_buffered = max_buffered

    def _run(self) -> Generator[Any, Any, None]:
        for move in self.moves:
            if moves_buffered(self.controller.axis(move.axis)) >= self.max_buffered:
                fields = {"host": self.name, "axis": move.axis, "process": self.process_no or 0}
                self.log.emit("host_blocked", **fields)
                while moves_buffered(self.controller.axis(move.axis)) >= self.max_buffered:
                    yield self.env.timeout(self.poll_period_s)
                self.log.emit("host_resumed", **fields)
            yield from self.place_blocking(move)
        self.finish()


__all__ = [
    "BlindFeeder",
    "Move",
    "MovesBufferedFeeder",
    "NtypeFeeder",
    "TrioFeeder",
    "interleave",
    "moves_buffered",
]
