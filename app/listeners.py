"""The controllers' own TCP protocols, started beside the REST service.

The hook: for each protocol below, :func:`start_listeners` imports the adapter module if it
is installed and awaits its server function with the controller's handle::

    api.pmac_ethernet.server.serve_pmac(handle, host, port, **kwargs) -> asyncio.Server
    api.trio_terminal.server.serve_trio(handle, host, port, **kwargs) -> asyncio.Server
    api.trio_modbus.server.serve_modbus(handle, host, port, **kwargs) -> asyncio.Server

``port`` 0 asks the OS for a free port; the port actually bound is read back from
``server.sockets``. The settings decide, per protocol (``pmac_port`` / ``trio_port`` /
``modbus_port``, which defaults to 0):

- ``None`` — the default port (1025 / 23). If it cannot be bound (23 is privileged for a
  non-root user; a port in use), or the adapter or the controller is missing, one line says so
  and that listener is skipped.
- an int — that port, and failing to bind it is an error (:class:`ListenerError`;
  ``motionsim serve`` exits with a non-zero status). ``0`` disables the listener.
- ``"auto"`` — a free port, printed.

The server function gets a :class:`motionsim.app.registry.LiveHandle` (the controller currently
registered under the id, so a deleted and re-created controller is served by its new
incarnation) and ``limits`` (:class:`motionsim.api.wire.ConnectionLimits`: connection cap, idle
timeout, from the settings ``tcp_max_connections`` / ``tcp_idle_timeout_s``).

Each listener started prints one line: ``motionsim listening pmac://127.0.0.1:1025 (controller
pmac)``. Extra keyword arguments (e.g. ``recorder=`` for ``--record``) are passed to every
server function.
"""

from __future__ import annotations

import asyncio
import importlib
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from .registry import Registry
from .settings import (
    DEFAULT_MODBUS_PORT,
    DEFAULT_PMAC_PORT,
    DEFAULT_TRIO_PORT,
    Settings,
)


class ListenerError(RuntimeError):
    """A protocol listener the user asked for could not be started."""


@dataclass(frozen=True, slots=True)
class Protocol:
    """One TCP protocol adapter: where it lives and what it serves."""

    name: str          # scheme in the "listening" line
    module: str        # adapter module
    function: str      # its ``async def serve_x(handle, host, port, **kw)``
    default_port: int
    setting: str       # Settings field with the port
    controller_setting: str  # Settings field with the controller id


@dataclass(frozen=True, slots=True)
class ConnectionLimits:
    """What one TCP protocol listener allows (settings ``tcp_max_connections``,
    ``tcp_idle_timeout_s``).

    ``max_connections``: connections open at once; one more closes the connection idle the
    longest (:mod:`motionsim.api.connection_table`), or is itself closed when every open one
    is in the middle of a command.
    ``idle_timeout_s``: a connection that sends nothing this long is closed.
    ``read_ahead_bytes``: input a connection may send ahead of the replies it has been given;
    beyond it the server stops reading (TCP flow control holds the host back) [INF].
    """

    max_connections: int = 32
    idle_timeout_s: float = 600.0
    read_ahead_bytes: int = 256 * 1024


@dataclass(frozen=True, slots=True)
class Listener:
    """A started protocol listener."""

    protocol: str
    controller: str
    host: str
    port: int
    server: asyncio.AbstractServer


PROTOCOLS: tuple[Protocol, ...] = (
    Protocol("pmac", "motionsim.api.pmac_ethernet.server", "serve_pmac", DEFAULT_PMAC_PORT,
             "pmac_port", "pmac_controller"),
    Protocol("telnet", "motionsim.api.trio_terminal.server", "serve_trio", DEFAULT_TRIO_PORT,
             "trio_port", "trio_controller"),
    Protocol("modbus", "motionsim.api.trio_modbus.server", "serve_modbus", DEFAULT_MODBUS_PORT,
             "modbus_port", "trio_controller"),
)


def _load(protocol: Protocol) -> Callable[..., Any] | None:
    try:
        module = importlib.import_module(protocol.module)
    except ModuleNotFoundError as exc:
        if exc.name and protocol.module.startswith(exc.name):
            return None
        raise
    return getattr(module, protocol.function, None)


async def start_listeners(
    registry: Registry,
    settings: Settings,
    *,
    out: Callable[[str], None] = print,
    **serve_kwargs: Any,
) -> list[Listener]:
    """Start the protocol listeners ``settings`` asks for; returns those started.

    Raises:
        ListenerError: an explicitly requested port could not be bound or served (the servers
            already started are closed first).
    """
    started: list[Listener] = []
    host = settings.host
    limits = ConnectionLimits(settings.tcp_max_connections, settings.tcp_idle_timeout_s)
    try:
        for protocol in PROTOCOLS:
            value = getattr(settings, protocol.setting)
            if value == 0:
                continue
            explicit = value is not None
            port = protocol.default_port if value is None else (0 if value == "auto" else value)
            cid = getattr(settings, protocol.controller_setting)

            def skip(why: str, protocol: Protocol = protocol, port: int = port,
                     explicit: bool = explicit) -> None:
                msg = f"{protocol.name} listener on {host}:{port}: {why}"
                if explicit:
                    raise ListenerError(msg)
                out(f"motionsim skipped {msg}")

            if cid not in registry:
                skip(f"no controller {cid!r}")
                continue
            serve = _load(protocol)
            if serve is None:
                skip(f"adapter {protocol.module} is not installed")
                continue
            try:
                server = await serve(registry.live(cid), host, port, limits=limits,
                                     **serve_kwargs)
            except OSError as exc:
                skip(f"cannot listen ({exc.strerror or exc})")
                continue
            bound = server.sockets[0].getsockname()[1] if server.sockets else port
            started.append(Listener(protocol.name, cid, host, bound, server))
            out(f"motionsim listening {protocol.name}://{host}:{bound} (controller {cid})")
    except BaseException:
        for listener in started:
            listener.server.close()
        raise
    return started


__all__ = ["PROTOCOLS", "ConnectionLimits", "Listener", "ListenerError", "Protocol",
           "start_listeners"]
