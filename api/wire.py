"""What the controllers' TCP protocol adapters share: the sans-I/O sentinel, the session base
and the one asyncio connection loop.

Each protocol (PMAC Ethernet, the Trio command line) is a codec (bytes ↔ typed requests, no
sockets) plus a *session*: one host connection's logic — it opens a controller port, records
the bytes it sees, runs each request through ``handle.command`` and yields the bytes to send.
:func:`serve_connection` is the only code here that touches asyncio streams; the replay
(:mod:`motionsim.app.replay`) drives sessions without any socket.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
from collections.abc import AsyncIterator, Callable
from typing import Any, Final

from ..app.fatal import exit_if_fatal
from ..app.faults import ReplyAction, faults_of, has_faults
from .connection_table import ConnectionTable, current_connection


class NeedData:
    """The type of :data:`NEED_DATA` (for annotations)."""

    __slots__ = ()

    def __repr__(self) -> str:
        return "NEED_DATA"


#: A codec has no complete request (or line) yet: feed it more bytes.
NEED_DATA: Final = NeedData()


class Disconnected(Exception):
    """The host went away while its command was still waiting for the controller."""


class ProtocolError(Exception):
    """The byte stream breaks the protocol; the connection must be closed."""


async def await_reply(reply: Any, gone: asyncio.Event | None = None) -> Any:
    """Wait for a :class:`motionsim.sim.controller.Reply` to complete (a pending PMAC reply arrives
    when the clock reaches the background cycle that answers it; a locked Trio terminal when the
    move is buffered).

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


class WireSession:
    """One host connection to a controller, without the socket.

    Subclasses set ``protocol`` (the recorder's name for it) and ``codec`` (with
    ``receive_data`` and an ``eof`` flag) and implement :meth:`replies`.

    Args:
        handle: the :class:`motionsim.app.registry.ControllerHandle` served.
        name: the controller port's name (``"tcp:127.0.0.1:5555"``), for messages.
        recorder: an :class:`motionsim.app.recorder.Recorder`, or None.
        peer: the host's address, for the transcript.
    """

    protocol: str = ""
    codec: Any

    def __init__(self, handle: Any, name: str, recorder: Any = None, peer: str = "") -> None:
        self.handle = handle
        self.port = handle.open_port(name)
        self.recorder = recorder
        self.session = (
            recorder.open_session(self.protocol, handle.id, self._now(), peer) if recorder else 0
        )
        self.closed = False
        #: Set when the host has gone: a command still waiting for its reply is given up.
        self.gone = asyncio.Event()
        #: The pump's wake-up (set by :func:`serve_connection`): a session with output of its
        #: own to send (Trio channel 0) sets it.
        self.wake: asyncio.Event | None = None
        #: An injected link fault for the next reply (:mod:`motionsim.app.faults`), or None.
        self.fault_action: ReplyAction | None = None

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

    def note_command(self, command: str) -> None:
        """A command line is about to run: an injected link fault may claim its reply."""
        controller = self.handle.controller
        if has_faults(controller):
            action = self.handle.apply(faults_of(controller).reply_action, command)
            if action is not None:
                self.fault_action = action

    def _out(self, data: bytes) -> bytes:
        """Record bytes about to be sent to the host; return them."""
        if self.recorder and data:
            self.recorder.record(self.session, "out", data, self._now())
        return data

    def replies(self) -> AsyncIterator[bytes]:
        """Handle everything complete received so far; yield the bytes to send."""
        raise NotImplementedError

    def close(self) -> None:
        """The host went away: release the port (and any buffer it held open)."""
        if self.closed:
            return
        self.closed = True
        with contextlib.suppress(Exception):
            self.handle.close_port(self.port)
        if self.recorder:
            self.recorder.close_session(self.session, self._now())


def peer_name(writer: asyncio.StreamWriter) -> str:
    """``host:port`` of the connection's remote end."""
    peer = writer.get_extra_info("peername")
    return f"{peer[0]}:{peer[1]}" if isinstance(peer, tuple) else str(peer)


def current_handle(source: Any) -> Any:
    """The controller handle a new connection talks to: ``source.current()`` for a listener's
    :class:`motionsim.app.registry.LiveHandle` (the controller registered under the id *now*;
    raises ``NotFound`` while there is none), else ``source`` itself."""
    current = getattr(type(source), "current", None)
    return source.current() if current is not None else source


def close_when_deleted(handle: Any, writer: asyncio.StreamWriter) -> Callable[[], None]:
    """Close ``writer``'s connection when ``handle``'s controller is deleted (no connection
    keeps driving a deleted controller); returns the unsubscribe."""
    on_close = getattr(handle, "on_close", None)
    if on_close is None:
        return lambda: None
    return on_close(writer.close)


async def read_chunk(reader: asyncio.StreamReader, limits: Any) -> bytes:
    """The next bytes from the host; ``b""`` when it closed or stayed silent past
    ``limits.idle_timeout_s`` (then the connection is closed as if the host had gone)."""
    try:
        # asyncio.timeout, not wait_for: no task is created per read (a round trip's cost)
        async with asyncio.timeout(limits.idle_timeout_s):
            data = await reader.read(65536)
    except TimeoutError:
        return b""
    connection = current_connection()
    if connection is not None:
        connection.touch()
    return data


#: Replies a connection sends in a row before the event loop serves everyone else once.
FAIR_SHARE = 4


async def serve_connection(
    session: WireSession,
    reader: asyncio.StreamReader,
    writer: asyncio.StreamWriter,
    log: logging.Logger,
    limits: Any = None,
) -> None:
    """Pump one connection: bytes in → ``session.receive``; ``session.replies()`` → bytes out.

    Reading runs as its own task so that a host going away is noticed while a command is still
    waiting for the controller. It reads at most ``limits.read_ahead_bytes`` ahead of the
    replies sent: a host pipelining input without reading its replies is held back by TCP flow
    control instead of filling the server's memory. A host silent for ``limits.idle_timeout_s``
    is disconnected; so is every connection of a controller that is deleted. A broken stream or
    an unexpected error closes this connection only; the server and the other connections keep
    running.
    """
    limits = limits if limits is not None else default_limits()
    peer = peer_name(writer)
    wake = asyncio.Event()
    session.wake = wake
    caught_up = asyncio.Event()
    ahead = 0

    async def read_loop() -> None:
        nonlocal ahead
        try:
            while True:
                if ahead > limits.read_ahead_bytes:
                    caught_up.clear()
                    await caught_up.wait()
                data = await read_chunk(reader, limits)
                ahead += len(data)
                session.receive(data)
                wake.set()
                if not data:
                    return
        except (ConnectionError, OSError):
            session.receive(b"")
            wake.set()

    unsubscribe = close_when_deleted(session.handle, writer)
    reading = asyncio.create_task(read_loop())
    connection = current_connection()
    working = connection.working if connection is not None else contextlib.nullcontext
    try:
        while True:
            await wake.wait()
            wake.clear()
            with working():
                await _send_replies(session, writer)
            ahead = 0
            caught_up.set()
            if session.codec.eof:
                break
    except (Disconnected, ConnectionError, OSError):
        pass
    except ProtocolError as exc:
        log.warning("%s %s: %s; closing the connection", session.protocol, peer, exc)
    except Exception as exc:  # noqa: BLE001 - one broken connection must not take the server down
        exit_if_fatal(exc)
        log.exception("%s %s: unexpected error; closing the connection", session.protocol, peer)
    finally:
        unsubscribe()
        reading.cancel()
        with contextlib.suppress(BaseException):
            await reading
        session.close()
        writer.close()
        with contextlib.suppress(Exception):
            await writer.wait_closed()


async def _send_replies(session: WireSession, writer: asyncio.StreamWriter) -> None:
    """Send the replies to everything the session has received so far."""
    answered = 0
    async for out in session.replies():
        answered += 1
        if answered % FAIR_SHARE == 0:
            # A host pipelining many requests whose answers need no simulated time would
            # otherwise keep the loop to itself: everyone else gets a turn in between.
            await asyncio.sleep(0)
        action, session.fault_action = session.fault_action, None
        if action is not None:
            await _faulty_reply(action, out, writer)
            continue
        writer.write(out)
        await writer.drain()


async def _faulty_reply(action: ReplyAction, out: bytes, writer: asyncio.StreamWriter) -> None:
    """Send ``out`` as an injected link fault says: late, not at all, or cut by a reset.

    Raises:
        ConnectionResetError: after a ``connection_reset`` (the connection is gone).
    """
    if action.kind == "reply_drop":
        return
    if action.kind == "reply_delay":
        await asyncio.sleep(action.delay_s)
        writer.write(out)
        await writer.drain()
        return
    keep = len(out) // 2 if action.after_bytes is None else min(action.after_bytes, len(out))
    if keep:
        writer.write(out[:keep])
        await writer.drain()
    writer.transport.abort()  # an RST, not an orderly close
    raise ConnectionResetError("injected connection_reset")


def default_limits() -> Any:
    from ..app.listeners import ConnectionLimits

    return ConnectionLimits()


async def start_server(
    connect: Callable[[asyncio.StreamReader, asyncio.StreamWriter], Any], host: str, port: int,
    limits: Any = None,
) -> asyncio.Server:
    """``asyncio.start_server`` whose connections end quietly when the server shuts down, with
    at most ``limits.max_connections`` open at once: one more makes the connection idle the
    longest close (:class:`motionsim.api.connection_table.ConnectionTable`); it is closed at
    once only when every open one is in the middle of a command."""
    limits = limits if limits is not None else default_limits()
    table = ConnectionTable(limits.max_connections, f"{host}:{port}")

    async def on_connect(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        connection = table.admit(writer)
        if connection is None:
            writer.close()
            return
        try:
            with contextlib.suppress(asyncio.CancelledError):
                await connect(reader, writer)
        finally:
            table.release(connection)

    return await asyncio.start_server(on_connect, host, port)


__all__ = [
    "NEED_DATA",
    "close_when_deleted",
    "current_handle",
    "default_limits",
    "read_chunk",
    "Disconnected",
    "NeedData",
    "ProtocolError",
    "WireSession",
    "await_reply",
    "peer_name",
    "serve_connection",
    "start_server",
]
