"""The Trio command-line server: telnet sessions ↔ :mod:`motionsim.api.trio_terminal.protocol` ↔
controller.

Each TCP session is a command line of process 0, shared with the REST terminal (API.md): every
line goes through ``await handle.command(line, port)`` on the same controller object, so a lock
taken from REST shows here and the other way round (``GET /terminal``, ``terminal`` events).
While a command is pending (a move that cannot be buffered) the prompt does not return and the
lines typed meanwhile wait, unread and unechoed, as on the controller (TN20: the terminal
"locks up" until the process buffer frees).
"""

from __future__ import annotations

import asyncio
import logging
from typing import Any

from motionsim.api.trio_terminal.protocol import TrioTerminalCodec
from motionsim.api.wire import (
    NEED_DATA,
    WireSession,
    await_reply,
    peer_name,
    serve_connection,
    start_server,
)
from motionsim.sim.errors import MotionSimError

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

    async def replies(self):  # noqa: ANN201 - async generator of bytes
        """Run every complete line received so far; yield the bytes to send (echo, replies).

        Raises:
            Disconnected: the host went away while a command was pending.
        """
        while True:
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

    async def execute(self, line: str) -> tuple[str, str | None]:
        """Run one line on process 0; the reply text and the error message (or None)."""
        try:
            reply = await self.handle.command(line, self.port)
            reply = await await_reply(reply, self.gone)
        except MotionSimError as exc:
            return "", exc.message
        return reply.reply, reply.error


async def serve_trio(handle: Any, host: str = "127.0.0.1", port: int = 23, *,
                     recorder: Any = None, echo: bool = True) -> asyncio.Server:
    """Listen for telnet sessions on ``handle``'s Trio command line (``port=0`` picks one)."""

    async def connect(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        peer = peer_name(writer)
        session = TrioSession(handle, f"telnet:{peer}", recorder, peer, echo)
        await serve_connection(session, reader, writer, log)

    return await start_server(connect, host, port)


__all__ = ["TrioSession", "serve_trio"]
