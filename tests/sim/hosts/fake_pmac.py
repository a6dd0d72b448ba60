"""A minimal stand-in PMAC for host-model tests: one rotary buffer, I16/I17 BREQ as the manual
describes, one line calculated as each move starts, every line a move of ``move_s``.

It has the public surface the hosts use (``env``, ``log``, ``load_lines``, ``rotary``, ``run``)
so the host models are tested without waiting for the real core; the scenario tests run the
real one.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass

import simpy
from motionsim.sim.errors import BufferFull
from motionsim.sim.events import EventLog


@dataclass
class LoadResult:
    accepted: int
    stored: int
    lines_ahead: int
    free_words: int
    breq: bool


class FakePmac:
    def __init__(self, *, i16: int = 5, i17: int = 10, move_s: float = 0.001, size: int = 600):
        self.env = simpy.Environment()
        self.log = EventLog(self.env, "fake", 1_000_000)
        self.i16, self.i17, self.move_s, self.size = i16, i17, move_s, size
        self.pending: deque[tuple[int, str]] = deque()
        self.n = 0
        self.breq = False
        self.used = 0
        self._more = None
        self.seen_seq = 0

    def rotary(self, cs: int) -> dict:
        return {"lines_ahead": len(self.pending), "breq": self.breq, "size_words": self.size,
                "used_words": self.used, "free_words": self.size - self.used, "open": False}

    def _set(self, level: bool) -> None:
        if level != self.breq:
            self.breq = level
            self.log.emit("breq", cs=1, level=level)

    def load_lines(self, cs: int, lines: list[str], first_seq: int | None = None) -> LoadResult:
        new = [
            ln for k, ln in enumerate(lines) if first_seq is None or first_seq + k > self.seen_seq
        ]
        if self.used + len(new) > self.size:
            raise BufferFull("no room")
        for ln in new:
            self.n += 1
            self.used += 1
            self.pending.append((self.n, ln))
            self.log.emit("line_loaded", cs=1, n=self.n, text=ln, words=1,
                          lines_ahead=len(self.pending))
            self._set(False)
            if len(self.pending) < self.i17:
                self._set(True)
        if first_seq is not None:
            self.seen_seq = max(self.seen_seq, first_seq + len(lines) - 1)
        if self._more is not None and not self._more.triggered and self.pending:
            self._more.succeed()
        return LoadResult(len(lines), len(new), len(self.pending), self.size - self.used, self.breq)

    def run(self, cs: int) -> None:
        self.log.emit("program", cs=1, state="running")
        self.env.process(self._exec())

    def _exec(self):
        env = self.env
        waiting = False
        while True:
            if not self.pending:
                if not waiting:
                    self.log.emit("program", cs=1, state="waiting")
                    waiting = True
                self._more = env.event()
                yield self._more
                continue
            if waiting:
                self.log.emit("program", cs=1, state="running")
                waiting = False
            n, _ = self.pending.popleft()
            self.log.emit("line_calculated", cs=1, n=n)
            if len(self.pending) < self.i16:
                self._set(True)
            self.log.emit("move_start", cs=1, n=n)
            yield env.timeout(self.move_s)
            self.used -= 1
            self.log.emit("move_end", cs=1, n=n)
