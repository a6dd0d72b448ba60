"""Hand-built event logs: emit events at chosen simulated times."""

from __future__ import annotations

import simpy
from motionsim.sim.events import EventLog


class Feed:
    def __init__(self) -> None:
        self.env = simpy.Environment()
        self.log = EventLog(self.env, "hand", 100_000)

    def at(self, t: float, type_: str, **fields) -> Feed:
        if t > self.env.now:
            self.env.run(until=t)
        self.log.emit(type_, **fields)
        return self

    def load(self, t: float, n: int, text: str = "X1") -> Feed:
        return self.at(t, "line_loaded", cs=1, n=n, text=text, words=1, lines_ahead=0)

    def events(self):
        return self.log.events()
