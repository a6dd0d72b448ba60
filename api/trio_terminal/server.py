"""The Trio command-line server: telnet sessions ↔ :mod:`motionsim.api.trio_terminal.protocol` ↔
controller.

Each TCP session is a command line of process 0, shared with the REST terminal (API.md): every
line goes through ``await handle.command(line, port)`` on the same controller object, so a lock
taken from REST shows here and the other way round (``GET /terminal``, ``terminal`` events).
While a command is pending (a move that cannot be buffered) the prompt does not return and the
lines typed meanwhile wait, unread and unechoed, as on the controller (TN20: the terminal
"locks up" until the process buffer frees).

Channel 0 output — a running program's ``PRINT`` and its run-time error line — is pushed to
every session as it is printed (each line ended by CR LF, no prompt after it), except while
the session's own command is pending, when it follows the reply.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
from typing import Any

from ...sim.errors import MotionSimError, NotFound
from ..wire import (
    NEED_DATA,
    WireSession,
    await_reply,
    current_handle,
    peer_name,
    serve_connection,
    start_server,
)
from .protocol import TrioTerminalCodec

log = logging.getLogger("motionsim.trio_terminal")


class TrioSession(WireSession):
    """One telnet session's logic, without the socket (the server and the replay drive it).

    Args:
        handle: the :class:`motionsim.app.registry.ControllerHandle` of the Trio served.
        name: the port name, for messages.
        recorder: an :class:`motionsim.app.recorder.Recorder`, or None.
    """

    protocol = "trio"

    def __init__(self, handle: Any, name: str, recorder: Any = None, peer: str = "",
                 echo: bool = True) -> None:
        self.codec = TrioTerminalCodec(echo=echo)
        super().__init__(handle, name, recorder, peer)
        channels = getattr(handle.controller, "channels", None)
        self._channels = channels
        self._cursor = channels.count if channels is not None else 0
        self._unlisten = handle.apply(channels.listen, self._printed) if channels else None

    def _printed(self) -> None:
        """A channel-0 line was printed: wake the connection's pump to send it."""
        if self.wake is not None:
            self.wake.set()

    def _output(self) -> bytes:
        """Channel-0 lines printed since the last call, as the terminal shows them."""
        if self._channels is None:
            return b""
        lines, self._cursor = self._channels.since(self._cursor)
        return b"".join(line.encode("latin-1", "replace") + b"\r\n" for line in lines)

    async def replies(self):  # noqa: ANN201 - async generator of bytes
        """Run every complete line received so far; yield the bytes to send (echo, replies).

        Raises:
            Disconnected: the host went away while a command was pending.
        """
        while True:
            printed = self._output()
            if printed:
                yield self._out(printed)
            line = self.codec.next_line()
            echo = self.codec.data_to_send()
            if echo:
                yield self._out(echo)
            if line is NEED_DATA:
                return
            if line.text.strip() == "":
                yield self._out(self.codec.reply())
                continue
            text, error = await self.execute(line.text)
            yield self._out(self.codec.reply(text, error))

    def close(self) -> None:
        if self._unlisten is not None and not self.closed:
            unlisten, self._unlisten = self._unlisten, None
            with contextlib.suppress(Exception):
                self.handle.apply(unlisten)
        super().close()

    async def execute(self, line: str) -> tuple[str, str | None]:
        """Run one line on process 0; the reply text and the error message (or None)."""
        self.note_command(line)
        try:
            reply = await self.handle.command(line, self.port)
            reply = await await_reply(reply, self.gone)
        except MotionSimError as exc:
            return "", exc.message
        return reply.reply, reply.error


async def serve_trio(handle: Any, host: str = "127.0.0.1", port: int = 23, *,
                     recorder: Any = None, echo: bool = True,
                     limits: Any = None) -> asyncio.Server:
    """Listen for telnet sessions on ``handle``'s Trio command line (``port=0`` picks one).

    ``handle`` and ``limits``: as for :func:`motionsim.api.pmac_ethernet.server.serve_pmac`
    (a session to a controller that is gone is closed)."""

    async def connect(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        peer = peer_name(writer)
        try:
            current = current_handle(handle)
        except NotFound:
            writer.close()
            return
        session = TrioSession(current, f"telnet:{peer}", recorder, peer, echo)
        await serve_connection(session, reader, writer, log, limits)

    return await start_server(connect, host, port, limits)


__all__ = ["TrioSession", "serve_trio"]
