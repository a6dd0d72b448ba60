"""A tiny controller kind for the spine's tests (independent of the PMAC / Trio work).

``dummy``: a ticker emits ``tick`` events every ``tick_s`` simulated seconds (cycle-indexed,
so deterministic); its terminal answers like a controller's host port, after
``reply_delay_s`` of simulated time:

- ``ECHO text`` -> ``text``; ``NOW text`` -> ``text`` at once; ``SLOW`` -> ``slow`` after 2 s
  (longer than the 1 s a virtual terminal waits, so it ends pending and the reply arrives as a
  ``terminal_reply`` event); ``ERR`` -> error ``ERR003``; ``HALT`` raises ``Halted``;
  ``OOM`` raises ``MemoryError``;
  ``ADDR n`` / ``ADDR?`` -> per-port modal state; ``PING`` emits a ``ping`` event at once.
- variables ``V0`` .. ``V9`` (0.0 by default); other names -> ``NotFound``.

``dummy_cmdline``: the same, but its command line never moves a virtual clock
(``terminal_wait_s = 0``, like the Trio's): a delayed reply returns pending at once.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from motionsim.app.kinds import register_kind
from motionsim.sim.controller import Controller, Port, Reply
from motionsim.sim.errors import Halted, InvalidValue, NotFound

_CONFIG = {"tick_s": 0.01, "reply_delay_s": 0.0005}


class DummyController(Controller):
    kind = "dummy"
    event_types = ("tick", "var", "ping")

    def __init__(self, id: str, config: Mapping[str, Any] | None = None, *,
                 log_capacity: int = 100_000) -> None:
        super().__init__(id, config, log_capacity=log_capacity)
        for key in self.config:
            if key not in _CONFIG:
                raise InvalidValue(f"unknown config key {key!r} for kind dummy",
                                   field=f"config.{key}")
        self.tick_s = float(self.config.get("tick_s", _CONFIG["tick_s"]))
        self.reply_delay_s = float(self.config.get("reply_delay_s", _CONFIG["reply_delay_s"]))
        self.ticks = 0
        self.variables: dict[str, float] = {}
        if self.tick_s > 0:
            self.env.process(self._ticker())

    def _ticker(self):
        k0 = round(self.env.now / self.tick_s)
        k = k0
        while True:
            k += 1
            yield self.env.timeout(k * self.tick_s - self.env.now)
            self.ticks += 1
            self.log.emit("tick", n=self.ticks)

    def _later(self, reply: Reply, delay: float, text: str, error: str | None = None):
        yield self.env.timeout(delay)
        reply.resolve(text, error, self.env.now)
        self.log.emit("terminal_reply", command=reply.command, reply=text, error=error)

    def terminal(self, command: str, port: Port | None = None) -> Reply:
        port = port or self.rest_port
        reply = Reply(command)
        word, _, rest = command.strip().partition(" ")
        word = word.upper()
        if word == "HALT":
            raise Halted("the dummy controller is halted")
        if word == "OOM":
            raise MemoryError("the dummy controller ran out of memory")
        if word == "NOW":
            reply.resolve(rest, None, self.env.now)
        elif word == "PING":
            self.log.emit("ping", text=rest)
            reply.resolve("", None, self.env.now)
        elif word == "ADDR":
            if rest == "?":
                reply.resolve(str(port.state.get("addr", 1)), None, self.env.now)
            else:
                port.state["addr"] = int(rest)
                reply.resolve("", None, self.env.now)
        elif word == "ECHO":
            self.env.process(self._later(reply, self.reply_delay_s, rest))
        elif word == "SLOW":
            self.env.process(self._later(reply, 2.0, "slow"))
        else:
            self.env.process(self._later(reply, self.reply_delay_s, "", "ERR003"))
        return reply

    def _name(self, name: str) -> str:
        key = name.upper()
        if len(key) != 2 or key[0] != "V" or not key[1].isdigit():
            raise NotFound(f"no variable {name!r} (the dummy has V0..V9)", variable=name)
        return key

    def get_variable(self, name: str) -> float:
        return self.variables.get(self._name(name), 0.0)

    def set_variable(self, name: str, value: float) -> None:
        key = self._name(name)
        if not math.isfinite(value):
            raise InvalidValue(f"{key} must be finite", field="value")
        self.variables[key] = float(value)
        self.log.emit("var", name=key, value=float(value))

    def reset(self) -> None:
        self.variables.clear()
        self.log.emit("reset")

    def status(self) -> dict[str, Any]:
        return {"ticks": self.ticks}


class DummyCmdline(DummyController):
    kind = "dummy_cmdline"
    terminal_wait_s = 0.0

    def terminal_state(self) -> dict[str, Any]:
        return {"locked": False, "pending": []}


register_kind(DummyController)
register_kind(DummyCmdline)
