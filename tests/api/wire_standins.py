"""Stand-in controller kinds for the wire-protocol tests (independent of the PMAC/Trio cores).

``wirepmac``: a host port that answers after a 0.5 ms background delay, Turbo-like I3=1 at power
on, per-port open buffer with the one-port rule (ERR005 / ERR007), ``HALT`` = watchdog tripped,
``NEVER`` = a reply that never comes. ``wiretrio``: a command line of process 0 whose ``MOVE``
cannot be buffered for 10 ms of simulated time (the terminal locks, later lines queue behind it).
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from typing import Any

from motionsim.app.kinds import register_kind
from motionsim.sim.controller import Controller, Port, Reply
from motionsim.sim.errors import Halted, NotFound

_IVAR = re.compile(r"^I(\d+)(?:=(-?\d+))?$", re.I)


class WirePmac(Controller):
    kind = "wirepmac"
    background_s = 0.0005

    def __init__(self, id: str, config: Mapping[str, Any] | None = None, *,
                 log_capacity: int = 100_000) -> None:
        super().__init__(id, config, log_capacity=log_capacity)
        self.ivars: dict[int, int] = {3: 1, 6: 1, 16: 5, 17: 10}
        self.holder: Port | None = None
        self.stored: list[str] = []
        self.commands: list[tuple[float, str, str]] = []

    def terminal(self, command: str, port: Port | None = None) -> Reply:
        port = port or self.rest_port
        if command.strip().upper() == "HALT":
            raise Halted("watchdog tripped")
        self.commands.append((self.now, port.name, command))
        self.log.emit("wire_command", port=port.name, command=command)
        reply = Reply(command)
        if command.strip().upper() == "NEVER":
            return reply
        self.env.process(self._answer(reply, command, port))
        return reply

    def _answer(self, reply: Reply, command: str, port: Port):
        yield self.env.timeout(self.background_s)
        data: list[str] = []
        error = None
        tokens = command.split()
        i = 0
        while i < len(tokens) and error is None:
            tok = tokens[i].upper()
            i += 1
            if tok == "VER":
                data.append("1.947  ")
            elif tok == "CID":
                data.append("603382")
            elif tok == "OPEN" and i < len(tokens) and tokens[i].upper() == "ROT":
                i += 1
                if self.holder is not None and self.holder is not port:
                    error = "ERR007"
                else:
                    self.holder = port
            elif tok == "CLOSE":
                if self.holder is port:
                    self.holder = None
            elif tok.startswith("X"):
                if self.holder is not port:
                    error = "ERR005"
                else:
                    self.stored.append(tok)
            elif m := _IVAR.match(tok):
                n = int(m.group(1))
                if m.group(2) is None:
                    data.append(str(self.ivars.get(n, 0)))
                else:
                    self.ivars[n] = int(m.group(2))
            else:
                error = "ERR003"
        reply.resolve("\r".join(data), error, self.now)

    def close_port(self, port: Port) -> None:
        super().close_port(port)
        if self.holder is port:
            self.holder = None

    def get_variable(self, name: str) -> float:
        m = _IVAR.match(name)
        if not m:
            raise NotFound(f"no variable {name}")
        return float(self.ivars.get(int(m.group(1)), 0))

    def set_variable(self, name: str, value: float) -> None:
        m = _IVAR.match(name)
        if not m:
            raise NotFound(f"no variable {name}")
        self.ivars[int(m.group(1))] = int(value)

    def reset(self) -> None:
        self.ivars = {3: 1, 6: 1, 16: 5, 17: 10}


class WireTrio(Controller):
    kind = "wiretrio"
    terminal_wait_s = 0.0
    move_wait_s = 0.010

    def __init__(self, id: str, config: Mapping[str, Any] | None = None, *,
                 log_capacity: int = 100_000) -> None:
        super().__init__(id, config, log_capacity=log_capacity)
        self.vr: dict[int, float] = {}
        self.queue: list[Reply] = []  # pending command-line lines, oldest first
        self.moves: list[tuple[float, str]] = []

    def terminal_state(self) -> dict[str, Any]:
        return {"locked": bool(self.queue), "pending": [r.command for r in self.queue]}

    def terminal(self, command: str, port: Port | None = None) -> Reply:
        reply = Reply(command)
        if self.queue:
            self.queue.append(reply)
            return reply
        self._run(reply)
        return reply

    def _run(self, reply: Reply) -> None:
        cmd = reply.command.strip()
        up = cmd.upper()
        if up.startswith("MOVE"):
            self.queue.insert(0, reply)
            self.log.emit("terminal", locked=True)
            self.env.process(self._buffered(reply))
            return
        if up.startswith("?") or up.startswith("PRINT"):
            expr = cmd[1:] if up.startswith("?") else cmd[5:]
            expr = expr.strip()
            m = re.fullmatch(r"VR\((\d+)\)", expr, re.I)
            try:
                value = self.vr.get(int(m.group(1)), 0.0) if m else float(expr)
            except ValueError:
                reply.resolve("", "%Command not recognised", self.now)
                return
            reply.resolve(f"{value:.4f}", None, self.now)
            return
        m = re.fullmatch(r"VR\((\d+)\)\s*=\s*(-?[\d.]+)", cmd, re.I)
        if m:
            self.vr[int(m.group(1))] = float(m.group(2))
            reply.resolve("", None, self.now)
            return
        reply.resolve("", "%Command not recognised", self.now)

    def _buffered(self, reply: Reply):
        yield self.env.timeout(self.move_wait_s)
        self.moves.append((self.now, reply.command))
        self.queue.remove(reply)
        reply.resolve("", None, self.now)
        self.log.emit("terminal", locked=False)
        self.log.emit("terminal_reply", command=reply.command, reply="", error=None)
        while self.queue and not self.queue[0].done:
            nxt = self.queue.pop(0)
            self._run(nxt)
            if not nxt.done:
                break

    def get_variable(self, name: str) -> float:
        m = re.fullmatch(r"VR\((\d+)\)", name, re.I)
        if not m:
            raise NotFound(f"no variable {name}")
        return self.vr.get(int(m.group(1)), 0.0)

    def set_variable(self, name: str, value: float) -> None:
        m = re.fullmatch(r"VR\((\d+)\)", name, re.I)
        if not m:
            raise NotFound(f"no variable {name}")
        self.vr[int(m.group(1))] = float(value)
        self.log.emit("vr", index=int(m.group(1)), value=float(value))

    def reset(self) -> None:
        self.vr.clear()


register_kind(WirePmac)
register_kind(WireTrio)
