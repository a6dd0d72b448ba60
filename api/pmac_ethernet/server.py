"""The PMAC Ethernet server: TCP connections ↔ :mod:`api.pmac_ethernet.protocol` ↔ controller.

Each TCP connection is one PMAC host port (``handle.open_port``) with its own ``&n`` / ``#n``
addressing and open buffer, so only one connection at a time may hold a buffer open (the
controller's rule). Every command line goes through ``await handle.command(line, port)`` —
the same controller object the REST terminal uses — so a line sent here shows in the event
log and on the WebSocket exactly like one posted over HTTP.

A request is executed only once it has fully arrived: a client that disconnects in the middle
of a WRITEBUFFER stores nothing. A broken stream (unknown request, oversized payload) closes
that connection only; the server and the other connections keep running. A watchdog-tripped
PMAC does not answer at all (spec §9.6: the CPU "will not communicate").
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
from collections.abc import AsyncIterator
from typing import Any

from api.pmac_ethernet.protocol import (
    NEED_DATA,
    Answer,
    CtrlResponse,
    GetResponse,
    PmacEthernetCodec,
    PortWrite,
    ProtocolError,
    SendLine,
    WriteBuffer,
    illegal_character,
)
from sim.errors import Halted, MotionSimError

log = logging.getLogger("motionsim.pmac_ethernet")


class _NoAnswer(Exception):
    """The controller will not answer (watchdog tripped)."""


class Disconnected(Exception):
    """The host went away while its command was still waiting for the controller."""


async def await_reply(reply: Any, gone: asyncio.Event | None = None) -> Any:
    """Wait for a :class:`sim.controller.Reply` to complete (a pending PMAC reply arrives when
    the clock reaches the background cycle that answers it).

    Raises:
        Disconnected: ``gone`` was set first (the host closed the connection).
    """
    if reply.done:
        return reply
    loop = asyncio.get_running_loop()
    fut: asyncio.Future[Any] = loop.create_future()

    def done(r: Any) -> None:
        if not fut.done():
            fut.set_result(r)

    reply.add_done_callback(done)
    if gone is None:
        return await fut
    waiter = asyncio.ensure_future(gone.wait())
    try:
        await asyncio.wait({fut, waiter}, return_when=asyncio.FIRST_COMPLETED)
    finally:
        waiter.cancel()
    if fut.done():
        return fut.result()
    fut.cancel()
    raise Disconnected()


class PmacSession:
    """One host connection's protocol logic, without the socket (the server and the replay
    both drive it).

    Args:
        handle: the :class:`app.registry.ControllerHandle` of the PMAC served.
        name: the port name (``"tcp:127.0.0.1:5555"``), for messages.
        recorder: an :class:`app.recorder.Recorder`, or None.
    """

    def __init__(self, handle: Any, name: str, recorder: Any = None, peer: str = "") -> None:
        self.handle = handle
        self.port = handle.open_port(name)
        self.codec = PmacEthernetCodec()
        self.recorder = recorder
        self.session = (
            recorder.open_session("pmac", handle.id, self._now(), peer) if recorder else 0
        )
        self.closed = False
        #: Set when the host has gone: a command still waiting for its reply is given up.
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

    async def replies(self) -> AsyncIterator[bytes]:
        """Execute every complete request received so far; yield each answer's bytes.

        Raises:
            ProtocolError: the stream is broken; close the connection.
        """
        while True:
            request = self.codec.next_request()
            if request is NEED_DATA:
                return
            try:
                out = await self._answer(request)
            except _NoAnswer:
                continue
            if self.recorder:
                self.recorder.record(self.session, "out", out, self._now())
            yield out

    async def _answer(self, request: Any) -> bytes:
        if isinstance(request, (GetResponse, SendLine)):
            answers = [await self.execute(line) for line in request.lines]
            return self.codec.reply(request, answers, **self._handshake())
        if isinstance(request, WriteBuffer):
            answers = []
            for line in request.lines:
                answer = await self.execute(line)
                answers.append(answer)
                if answer.error is not None:
                    break
            return self.codec.reply(request, answers)
        if isinstance(request, CtrlResponse):
            answer = await self.execute(chr(request.char))
            return self.codec.reply(request, [answer], **self._handshake())
        if isinstance(request, PortWrite):
            line = self.codec.port_write(request.char)
            answers = [await self.execute(line)] if line is not None else []
            return self.codec.reply(request, answers, **self._handshake())
        return self.codec.reply(request)

    def _handshake(self) -> dict[str, int]:
        """The controller's current I3 and I6 (2 and 1 if it has no such variables)."""
        out = {"i3": 2, "i6": 1}
        for name in ("i3", "i6"):
            # kinds without I-variables keep the defaults
            with contextlib.suppress(Exception):
                out[name] = int(self.handle.controller.get_variable(name.upper()))
        return out

    async def execute(self, line: str) -> Answer:
        """Run one command line on the controller; its data lines and error code."""
        if line.strip() == "":
            return Answer()
        if illegal_character(line) is not None:
            return Answer(error="ERR004")
        try:
            reply = await self.handle.command(line, self.port)
            reply = await await_reply(reply, self.gone)
        except Halted:
            raise _NoAnswer() from None
        except MotionSimError as exc:
            return Answer(error=exc.pmac_error or "ERR003")
        return Answer.from_reply(reply.reply, reply.error)

    def close(self) -> None:
        """The host went away: release the port (and any buffer it held open)."""
        if self.closed:
            return
        self.closed = True
        with contextlib.suppress(Exception):
            self.handle.close_port(self.port)
        if self.recorder:
            self.recorder.close_session(self.session, self._now())


async def _serve_connection(
    handle: Any, reader: asyncio.StreamReader, writer: asyncio.StreamWriter, recorder: Any
) -> None:
    peer = writer.get_extra_info("peername")
    peer_s = f"{peer[0]}:{peer[1]}" if isinstance(peer, tuple) else str(peer)
    session = PmacSession(handle, f"tcp:{peer_s}", recorder, peer_s)
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
    except Disconnected:
        pass
    except ProtocolError as exc:
        log.warning("PMAC Ethernet %s: %s; closing the connection", peer_s, exc)
    except (ConnectionError, OSError):
        pass
    except Exception:  # noqa: BLE001 - one broken connection must not take the server down
        log.exception("PMAC Ethernet %s: unexpected error; closing the connection", peer_s)
    finally:
        reading.cancel()
        with contextlib.suppress(BaseException):
            await reading
        session.close()
        writer.close()
        with contextlib.suppress(Exception):
            await writer.wait_closed()


async def serve_pmac(
    handle: Any, host: str = "127.0.0.1", port: int = 1025, *, recorder: Any = None
) -> asyncio.Server:
    """Listen for PMAC Ethernet connections to ``handle``'s controller (``port=0`` picks one).

    Returns the started :class:`asyncio.Server`; ``server.sockets[0].getsockname()[1]`` is
    the port bound.
    """

    async def on_connect(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        # the server shutting down cancels its connections: end quietly
        with contextlib.suppress(asyncio.CancelledError):
            await _serve_connection(handle, reader, writer, recorder)

    return await asyncio.start_server(on_connect, host, port)


__all__ = ["Disconnected", "PmacSession", "await_reply", "serve_pmac"]
