"""Program-originated messages: ``SEND{port}"text"`` lines on their way to the host.

What the manuals say (spec §12.2, §2.1, §2.3):

* ``SEND"text"`` sends an unsolicited text line; ``SENDS`` always to the main serial port,
  ``SENDP`` to the parallel (bus) host port, ``SENDR`` to the DPRAM ASCII response buffer,
  ``SENDA`` to the auxiliary serial port (TSRM p470). A plain ``SEND`` goes to the *active
  response port*: the port that most recently received a host command (PSRM p347, PMAC(1)
  page; ``[INF]`` the same on Turbo).
* The line is framed like a data line of a command reply per I3 (a leading ``<LF>`` with
  I3=1 or 3, a trailing ``<CR>``) but never gets the trailing ACK/LF of a host command
  (TSRM p37). With I64=1 it starts with ``<STX>`` so a host can tell it from a reply
  (TSRM p67); the Ethernet GETRESPONSE then returns only up to its ``<CR>`` (spec §5.1).

What the simulator does ``[INF]``:

* Its host ports — the Ethernet connections and the REST terminal — stand in for the
  bus/Ethernet host port: ``SEND`` and ``SENDP`` go to the active response port (the host
  port whose command line was executed last). The card has no serial, auxiliary serial or
  DPRAM ASCII port, so a ``SENDS`` / ``SENDA`` / ``SENDR`` line reaches no wire port
  (:data:`ROUTES`).
* Every line, whatever its port, is kept for the REST terminal (``output`` of the next
  ``POST .../terminal``) and logged as an event by the sender (``plc_send`` / ``program_send``).
* The store is bounded: the last :data:`MAX_LINES` lines. A real card keeps an unread line
  queued and halts the sending program once several back up (PSRM p347); the simulator
  instead drops the oldest line, and when that line had not been read by the port it was
  sent to it logs a ``host_message_dropped`` event with the running count.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Final

from ...controller import Port

#: Lines kept for the host ports, oldest first; beyond it the oldest is dropped.
MAX_LINES: Final = 256

#: ``SEND`` port letter -> whether a simulated wire port receives the line (the active
#: response port); the others name ports the simulated card does not have ``[INF]``.
ROUTES: Final[dict[str, bool]] = {"": True, "P": True, "S": False, "A": False, "R": False}

#: Per-port state key: ``(store, sequence number)`` of the last message the port has read.
_READ: Final = "messages_read"

STX: Final = "\x02"


@dataclass(frozen=True, slots=True)
class Message:
    """One ``SEND`` line: its sequence number, time, sender, port letter, text and the
    host port it was sent to (None: a port the simulator does not have)."""

    seq: int
    t: float
    source: str
    port: str
    text: str
    target: Port | None


def frame(text: str, i3: int, i64: int) -> bytes:
    """The bytes of one program-originated line per I3 and I64 (no ACK, TSRM p37, p67)."""
    lead = "\n" if int(i3) & 3 in (1, 3) else ""
    stx = STX if int(i64) & 1 else ""
    return (lead + stx + text + "\r").encode("latin-1", "replace")


class HostMessages:
    """The card's outgoing program messages and which port has read how far."""

    def __init__(self, emit: Callable[..., Any], now: Callable[[], float]) -> None:
        self._emit = emit
        self._now = now
        self.lines: deque[Message] = deque()
        self.seq = 0
        self.dropped = 0
        #: The host port whose command line was executed last (PSRM p347).
        self.active: Port | None = None

    def send(self, source: str, port: str, text: str) -> Message:
        """Queue ``text`` from ``source`` (``"plc3"``, ``"cs1"``) for port letter ``port``."""
        self.seq += 1
        target = self.active if ROUTES.get(port, False) else None
        msg = Message(self.seq, self._now(), source, port, text, target)
        if len(self.lines) >= MAX_LINES:
            self._drop(self.lines.popleft())
        self.lines.append(msg)
        return msg

    def _read(self, port: Port) -> int:
        """The last sequence number ``port`` has read from this store (a reset makes a new
        store: marks of the old one count as nothing read)."""
        mark = port.state.get(_READ)
        return mark[1] if mark is not None and mark[0] is self else 0

    def _drop(self, old: Message) -> None:
        target = old.target
        if target is None or target.closed or self._read(target) >= old.seq:
            return
        self.dropped += 1
        self._emit("host_message_dropped", source=old.source, port=old.port or "host",
                   text=old.text, dropped=self.dropped)

    def take_for(self, port: Port) -> list[Message]:
        """The lines sent to ``port`` that it has not read yet, oldest first; marks them read."""
        read = self._read(port)
        if not self.lines or self.lines[-1].seq <= read:
            return []
        out = [m for m in self.lines if m.seq > read and m.target is port]
        port.state[_READ] = (self, self.lines[-1].seq)
        return out

    def since(self, cursor: int, port: Port | None = None) -> tuple[list[str], int]:
        """Every line's text after sequence number ``cursor``, and the new cursor; ``port``
        (the REST terminal's) has then read the lines sent to it."""
        if port is not None:
            port.state[_READ] = (self, self.seq)
        return [m.text for m in self.lines if m.seq > cursor], self.seq


__all__ = ["MAX_LINES", "ROUTES", "HostMessages", "Message", "frame"]
