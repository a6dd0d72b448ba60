"""Helpers for PMAC tests: a controller on a virtual clock, driven step by step.

Times are asserted in servo cycles (``cyc(t)``): every instant the PMAC core emits is a
whole servo cycle, and RTIs are the cycles divisible by I8+1 (3 by default).
"""

from __future__ import annotations

from typing import Any

import pytest
from motionsim.sim.controller import Port, Reply
from motionsim.sim.pmac import PmacController


class Rig:
    """A PmacController plus test conveniences."""

    def __init__(self, **config: Any) -> None:
        self.c = PmacController("pmac", config)
        self.period = self.c.scheduler.period_s

    def cmd(self, text: str, port: Port | None = None) -> Reply:
        """Send a terminal line and run the simulation until it is answered."""
        reply = self.c.terminal(text, port)
        env = self.c.env
        while not reply.done:
            env.step()
        return reply

    def ok(self, text: str, port: Port | None = None) -> str:
        reply = self.cmd(text, port)
        assert reply.error is None, f"{text!r} -> {reply.error}"
        return reply.reply

    def run_for(self, seconds: float) -> None:
        self.c.env.run(until=self.c.env.now + seconds)

    def run_until_idle(self, limit_s: float = 60.0) -> None:
        env = self.c.env
        end = env.now + limit_s
        while env.peek() <= end:
            env.step()

    def cyc(self, t: float) -> int:
        k = round(t / self.period)
        assert abs(k * self.period - t) < 1e-9, f"{t} is not on a servo cycle"
        return k

    def events(self, *types: str, since: int = 0) -> list[tuple[int, str, dict]]:
        """``(cycle, type, fields)`` of the log."""
        return [
            (self.cyc(e.t), e.type, dict(e.fields))
            for e in self.c.log.read(since, types or None).events
        ]

    def by_n(self, type_: str) -> dict[int, int]:
        """Program line number -> the cycle of its (latest) ``type_`` event."""
        return {f["n"]: k for k, _, f in self.events(type_)}

    def ms_cycles(self, ms: float) -> float:
        return ms / 1000.0 / self.period

    def assert_refused_err003(self, line: str, column: int) -> None:
        """``line`` sent to an open rotary buffer is ``ERR003`` and stores nothing (no words,
        no ``line_loaded``); loaded through the API it fails at 1-based ``column``."""
        self.rotary_setup()
        port = self.c.open_port("host")
        self.ok("OPEN ROT", port)
        since = self.c.log.last_seq
        words = self.c.rotary(1)["used_words"]
        reply = self.cmd(line, port)
        assert reply.error is not None and "ERR003" in str(reply.error)
        assert self.c.rotary(1)["used_words"] == words
        assert self.events("line_loaded", since=since) == []
        with pytest.raises(Exception) as exc:
            self.c.load_lines(1, [line])
        assert getattr(exc.value, "column", None) == column

    def rotary_setup(self, words: int = 600, cs: int = 1) -> None:
        self.ok(f"&{cs} DEFINE ROT {words}")
        self.ok(f"&{cs} B0")


@pytest.fixture
def rig() -> Rig:
    return Rig()


@pytest.fixture
def make_rig():
    return Rig
