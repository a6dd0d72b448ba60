"""The Trio command-line server: telnet sessions ↔ :mod:`api.trio_terminal.protocol` ↔ controller.

Each TCP session is a command line of process 0, shared with the REST terminal (API.md): every
line goes through ``await handle.command(line, port)`` on the same controller object, so a lock
taken from REST shows here and the other way round (``GET /terminal``, ``terminal`` events).
While a command is pending (a move that cannot be buffered) the prompt does not return and the
lines typed meanwhile wait, unread and unechoed, as on the controller (TN20: the terminal
"locks up" until the process buffer frees).
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
from typing import Any

from api.pmac_ethernet.server import Disconnected, await_reply
from api.trio_terminal.protocol import NEED_DATA, TrioTerminalCodec
from sim.errors import MotionSimError

log = logging.getLogger("motionsim.trio_terminal")


class TrioSession:
    """One telnet session's logic, without the socket (the server and the replay drive it).

    Args:
        handle: the :class:`app.registry.ControllerHandle` of the Trio served.
        name: the port name, for messages.
        recorder: an :class:`app.recorder.Recorder`, or None.
    """

    def __init__(self, handle: Any, name: str, recorder: Any = None, peer: str = "",
                 echo: bool = True) -> None:
        self.handle = handle
        self.port = handle.open_port(name)
        self.codec = TrioTerminalCodec(echo=echo)
        self.recorder = recorder
        self.session = (
            recorder.open_session("trio", handle.id, self._now(), peer) if recorder else 0
        )
        self.closed = False
        self.gone = asyncio.Event()

    def _now(self) -> float:
        """Simulated now (a realtime clock's reading, which runs ahead of a lazily synced env)."""
        try:
            return float(self.handle.clock.t)
        except Exception:  # noqa: BLE001 - a stand-in handle without a clock
            return float(getattr(self.handle.controller, "now", 0.0))

    def receive(self, data: bytes) -> None:
        """Bytes from the host (``b""`` = the host closed its side)."""
        if self.recorder and data:
            self.recorder.record(self.session, "in", data, self._now())
        self.codec.receive_data(data)
        if not data:
            self.gone.set()

    def _out(self, data: bytes) -> bytes:
        if self.recorder and data:
            self.recorder.record(self.session, "out", data, self._now())
        return data

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

    def close(self) -> None:
        """The host went away: release the port."""
        if self.closed:
            return
        self.closed = True
        with contextlib.suppress(Exception):
            self.handle.close_port(self.port)
        if self.recorder:
            self.recorder.close_session(self.session, self._now())


async def _serve_connection(handle: Any, reader: asyncio.StreamReader,
                            writer: asyncio.StreamWriter, recorder: Any, echo: bool) -> None:
    peer = writer.get_extra_info("peername")
    peer_s = f"{peer[0]}:{peer[1]}" if isinstance(peer, tuple) else str(peer)
    session = TrioSession(handle, f"telnet:{peer_s}", recorder, peer_s, echo)
    wake = asyncio.Event()

    async def read_loop() -> None:
        try:
            while True:
                data = await reader.read(65536)
                session.receive(data)
                wake.set()
                if not data:
                    return
        except (ConnectionError, OSError):
            session.receive(b"")
            wake.set()

    reading = asyncio.create_task(read_loop())
    try:
        while True:
            await wake.wait()
            wake.clear()
            async for out in session.replies():
                writer.write(out)
                await writer.drain()
            if session.codec.eof:
                break
    except (Disconnected, ConnectionError, OSError):
        pass
    except Exception:  # noqa: BLE001 - one broken session must not take the server down
        log.exception("Trio terminal %s: unexpected error; closing the session", peer_s)
    finally:
        reading.cancel()
        with contextlib.suppress(BaseException):
            await reading
        session.close()
        writer.close()
        with contextlib.suppress(Exception):
            await writer.wait_closed()


async def serve_trio(handle: Any, host: str = "127.0.0.1", port: int = 23, *,
                     recorder: Any = None, echo: bool = True) -> asyncio.Server:
    """Listen for telnet sessions on ``handle``'s Trio command line (``port=0`` picks one)."""

    async def on_connect(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        # the server shutting down cancels its connections: end quietly
        with contextlib.suppress(asyncio.CancelledError):
            await _serve_connection(handle, reader, writer, recorder, echo)

    return await asyncio.start_server(on_connect, host, port)


__all__ = ["TrioSession", "serve_trio"]
