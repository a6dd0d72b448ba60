"""The PMAC Ethernet server: TCP connections ↔ :mod:`motionsim.api.pmac_ethernet.protocol` ↔
controller.

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

from ...sim.errors import Halted, MotionSimError, NotFound
from ..wire import (
    NEED_DATA,
    WireSession,
    await_reply,
    current_handle,
    peer_name,
    serve_connection,
    start_server,
)
from .protocol import (
    Answer,
    CtrlResponse,
    GetResponse,
    PmacEthernetCodec,
    PortWrite,
    SendLine,
    WriteBuffer,
    illegal_character,
)

log = logging.getLogger("motionsim.pmac_ethernet")


class _NoAnswer(Exception):
    """The controller will not answer (watchdog tripped)."""


class PmacSession(WireSession):
    """One host connection's protocol logic, without the socket (the server and the replay
    both drive it).

    Args:
        handle: the :class:`motionsim.app.registry.ControllerHandle` of the PMAC served.
        name: the port name (``"tcp:127.0.0.1:5555"``), for messages.
        recorder: an :class:`motionsim.app.recorder.Recorder`, or None.
    """

    protocol = "pmac"

    def __init__(self, handle: Any, name: str, recorder: Any = None, peer: str = "") -> None:
        self.codec = PmacEthernetCodec()
        self._handshake_key: tuple[Any, int] | None = None
        self._handshake_io: dict[str, int] = {}
        super().__init__(handle, name, recorder, peer)

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
            yield self._out(out)

    def _deliver(self) -> None:
        """Queue the ``SEND`` lines the card's programs sent to this port since the last
        request, ahead of what this request produces (sim.pmac.host.messages)."""
        take = getattr(self.handle.controller, "host_messages", None)
        if take is None or self.port is None:
            return
        for data, _text in take(self.port):
            self.codec.unsolicited(data)

    async def _answer(self, request: Any) -> bytes:
        self._deliver()
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
        """The controller's current I3 and I6 (2 and 1 if it has no such variables).

        Read once per change: a PMAC's ``vars.version`` moves on every I-variable write, so
        the pair is kept until it moves (the round trip's hot path reads no variable)."""
        controller = self.handle.controller
        variables = getattr(controller, "vars", None)
        version = getattr(variables, "version", None)
        key = (variables, version)
        if version is not None and self._handshake_key is not None \
                and self._handshake_key[0] is variables and self._handshake_key[1] == version:
            return self._handshake_io
        out = {"i3": 2, "i6": 1}
        for name in ("i3", "i6"):
            # kinds without I-variables keep the defaults
            with contextlib.suppress(Exception):
                out[name] = int(controller.get_variable(name.upper()))
        if version is not None:
            self._handshake_key, self._handshake_io = key, out
        return out

    async def execute(self, line: str) -> Answer:
        """Run one command line on the controller; its data lines and error code."""
        if line.strip(" \t") == "":
            return Answer()  # (str.strip() would also drop CTRL-K and CTRL-L, which are commands)
        if illegal_character(line) is not None:
            return Answer(error="ERR004")
        self.note_command(line)
        try:
            reply = await self.handle.command(line, self.port)
            reply = await await_reply(reply, self.gone)
        except Halted:
            raise _NoAnswer() from None
        except MotionSimError as exc:
            return Answer(error=exc.pmac_error or "ERR003")
        return Answer.from_reply(reply.reply, reply.error)


async def serve_pmac(
    handle: Any, host: str = "127.0.0.1", port: int = 1025, *, recorder: Any = None,
    limits: Any = None,
) -> asyncio.Server:
    """Listen for PMAC Ethernet connections to ``handle``'s controller (``port=0`` picks one).

    ``handle`` may be a :class:`motionsim.app.registry.LiveHandle`: each connection then talks
    to the controller registered under its id when it connects (none: the connection is
    closed). ``limits``: :class:`motionsim.app.listeners.ConnectionLimits`. Returns the started
    :class:`asyncio.Server`; ``server.sockets[0].getsockname()[1]`` is the port bound.
    """

    async def connect(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        peer = peer_name(writer)
        try:
            current = current_handle(handle)
        except NotFound:
            writer.close()
            return
        session = PmacSession(current, f"tcp:{peer}", recorder, peer)
        await serve_connection(session, reader, writer, log, limits)

    return await start_server(connect, host, port, limits)


__all__ = ["PmacSession", "serve_pmac"]
