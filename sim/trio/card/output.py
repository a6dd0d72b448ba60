"""Program output: PRINT, PRINT #n, OUTDEVICE, the channels, and channel 0's listeners.

* ``OUTDEVICE`` is a process parameter choosing the channel that process' ``PRINT`` writes
  to (TRM MC206 p. 8-130, M206-320; channel numbers as for INDEVICE); ``PRINT #n, ...`` names
  the channel for one statement (M206-475, PRINT# in the chapter-8 index).
* Channel 0 is the command-line terminal (TN20: "terminal channel 0"): in the simulator the
  telnet sessions, the REST terminal and the ``print`` events. A program's run-time error
  line (``%[Process n:Line l] - ...``) is printed there too ``[INF]``.
* The other channels have no device here (``[BK]`` MC2xx: 1 serial B, 2 RS-485, 5–7 Motion
  Perfect windows, 3–4 network/other; spec §10.8): their lines are only ``print`` events with
  their ``channel``. Channels 0..9 exist ``[INF]``; another number is a run-time error.

Every line is a ``print`` event ``{"process", "channel", "text"}``; channel-0 lines are also
kept (the last :data:`KEEP` of them) for consumers reading with a cursor — the telnet server
pushes them to its sessions, the REST terminal returns those printed since its previous
command — and listeners are told as they are written.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable

from ...events import EventLog
from .basic_errors import BasicError

#: Channel-0 lines kept for cursor readers (older ones are dropped, counted in ``dropped``).
KEEP = 1000
CHANNELS = range(10)


class Channels:
    """The output channels of one controller."""

    def __init__(self, log: EventLog) -> None:
        self.log = log
        self._lines: deque[str] = deque(maxlen=KEEP)
        self.count = 0  # channel-0 lines written since power-up
        self._listeners: list[Callable[[], None]] = []

    @staticmethod
    def check(channel: float) -> int:
        """The channel number of ``PRINT #n`` / ``OUTDEVICE`` (a BasicError if none)."""
        n = int(channel)
        if n != channel or n not in CHANNELS:
            raise BasicError(f"Channel number out of range: {channel:g}")
        return n

    def write(self, process: int, channel: int, text: str) -> None:
        """One complete output line of ``process`` on ``channel``."""
        self.log.emit("print", process=process, channel=channel, text=text)
        if channel == 0:
            self._lines.append(text)
            self.count += 1
            for cb in list(self._listeners):
                cb()

    def since(self, cursor: int) -> tuple[list[str], int]:
        """Channel-0 lines written after ``cursor`` (a former ``count``) and the new cursor."""
        n = min(self.count - cursor, len(self._lines))
        lines = list(self._lines)[len(self._lines) - n:] if n > 0 else []
        return lines, self.count

    def listen(self, callback: Callable[[], None]) -> Callable[[], None]:
        """Call ``callback()`` after each channel-0 line; returns the function that stops it."""
        self._listeners.append(callback)

        def stop() -> None:
            if callback in self._listeners:
                self._listeners.remove(callback)

        return stop


__all__ = ["CHANNELS", "KEEP", "Channels"]
