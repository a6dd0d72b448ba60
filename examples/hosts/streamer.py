"""A host that keeps a PMAC rotary buffer fed over REST: the code under test in the examples.

It is deliberately ordinary host code: on a BREQ (buffer request) it tops the rotary buffer up
to I17 lines ahead, in one batch, and starts the program after the first batch. How it learns
that BREQ went high is the part that changes with the way time is driven (see the three
examples beside this file); ``refill`` is the same in all three.

``delay_s`` makes it a *slow* host: it takes that long (simulated seconds) between seeing BREQ
and writing. Beyond the time the lines still ahead cover (fewer than I16 when BREQ rises), the
program runs out of lines: the examples' assertion ``"waiting" not in states`` must then fail.
"""

from __future__ import annotations

import sys
import threading
import time
from collections.abc import Callable, Iterator
from typing import Any

from motionsim.app.client import MotionSimClient, PacedHost

#: Each line is a 100 ms move; I16 = 5 lines ahead leaves ~0.5 s before the program starves.
I16, I17 = 5, 10
MOVE_MS = 100


def program() -> Iterator[str]:
    """An endless program: alternating 100 ms moves on X."""
    i = 0
    while True:
        i += 1
        yield f"TM{MOVE_MS} TA10 TS0 X{(i % 2) * 10}"


class Streamer:
    """Tops up ``cs``'s rotary buffer of controller ``id`` to I17 lines on each refill."""

    def __init__(self, client: MotionSimClient, id: str = "pmac", cs: int = 1,
                 i17: int = I17) -> None:
        self.client = client
        self.i17 = i17
        self.id = id
        self.cs = cs
        self.lines = program()
        self.sent = 0
        self.started = False

    def breq(self) -> bool:
        """The BREQ level now (what a host reads from the card's status)."""
        return bool(self.client.coord(self.id, self.cs)["rotary"]["breq"])

    def refill(self) -> int:
        """Send lines up to ``i17`` ahead in one batch (and ``B0 R`` the first time)."""
        ahead = self.client.coord(self.id, self.cs)["rotary"]["lines_ahead"]
        batch = [next(self.lines) for _ in range(max(0, self.i17 - ahead))]
        if batch:
            self.client.load_lines(self.id, self.cs, batch)
            self.sent += len(batch)
        if not self.started:
            self.client.run(self.id, self.cs)
            self.started = True
        return len(batch)


class PacedStreamerThread(threading.Thread):
    """The streamer in its own thread on a host-paced clock (holder ``host.holder``): waits
    for each BREQ rising edge, takes ``delay_s`` to react, refills. Errors are re-raised by
    :meth:`join_checked` so a failing host fails the test instead of printing a warning."""

    def __init__(self, host: PacedHost, delay_s: float = 0.0) -> None:
        super().__init__(name=f"streamer-{host.holder}", daemon=True)
        self.host = host
        self.delay_s = delay_s
        self.streamer = Streamer(host.client, host.id)
        self.error: BaseException | None = None

    def run(self) -> None:
        try:
            if not self.streamer.breq():  # a defined REST buffer asks for lines at once
                self.host.wait_for("breq", 5.0, cs=self.streamer.cs, level=True)
            while not self.host.released:
                if self.delay_s:
                    self.host.sleep(self.delay_s)
                self.streamer.refill()
                self.host.wait_for("breq", 5.0, cs=self.streamer.cs, level=True)
        except BaseException as exc:  # handed to the test by join_checked
            self.error = exc
        finally:
            self.host.close()

    def join_checked(self, timeout: float = 30.0) -> None:
        self.join(timeout)
        if self.is_alive():
            raise TimeoutError(f"{self.name} did not stop")
        if self.error is not None:
            raise self.error


def starved(events: list[dict[str, Any]]) -> bool:
    """The README's check: did the program ever run out of lines?"""
    return "waiting" in [e["state"] for e in events if e["type"] == "program"]


def play(run: Callable[..., list[dict[str, Any]]], **kwargs: Any) -> tuple[list, float]:
    """``run(client, **kwargs)`` against a fresh in-process service: (event log, wall s)."""
    from motionsim.app.embedded import EmbeddedService
    from motionsim.app.settings import Settings

    settings = Settings(port=0, controllers=[], pmac_port=0, trio_port=0)
    with EmbeddedService(settings) as svc, MotionSimClient(svc.url) as ms:
        start = time.monotonic()
        events = run(ms, **kwargs)
        return events, time.monotonic() - start


def main(run: Callable[..., list[dict[str, Any]]], label: str, sim_s: float) -> None:
    """An example's command line: ``[delay_s]``; prints what happened."""
    delay_s = float(sys.argv[1]) if len(sys.argv) > 1 else 0.0
    events, wall = play(run, delay_s=delay_s)
    moves = sum(e["type"] == "move_end" for e in events)
    print(f"{label}, host delay {delay_s:g} s: {sim_s:g} simulated s in {wall:.2f} wall s, "
          f"{moves} moves, {'STARVED' if starved(events) else 'kept fed'}")
