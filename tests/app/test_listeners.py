"""The protocol-listener hook: defaults skipped with one line, explicit ports must bind."""

from __future__ import annotations

import asyncio
import socket
import sys
import types

import pytest
from motionsim.app import listeners as L
from motionsim.app.registry import Registry
from motionsim.app.settings import Settings

import tests.dummy_kind  # noqa: F401


@pytest.fixture
def fake_adapter(monkeypatch):
    """A stand-in adapter module whose serve function echoes one line per connection."""
    mod = types.ModuleType("fake_adapter_server")
    calls = []

    async def serve_fake(handle, host, port, **kwargs):
        calls.append((handle.id, host, port, kwargs))

        async def on_connect(reader, writer):
            writer.write((await reader.readline()).upper())
            await writer.drain()
            writer.close()

        return await asyncio.start_server(on_connect, host, port)

    mod.serve_fake = serve_fake
    monkeypatch.setitem(sys.modules, "fake_adapter_server", mod)
    proto = L.Protocol("fake", "fake_adapter_server", "serve_fake", 0, "pmac_port",
                       "pmac_controller")
    monkeypatch.setattr(L, "PROTOCOLS", (proto,))
    return proto, calls


def _registry():
    reg = Registry()
    reg.add("dummy", "pmac", clock="virtual")
    return reg


def _busy_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    s.listen(1)
    return s, s.getsockname()[1]


async def _start(settings, **kw):
    lines = []
    started = await L.start_listeners(_registry(), settings, out=lines.append, **kw)
    return started, lines


def test_auto_port_is_bound_served_and_printed(fake_adapter):
    async def main():
        started, lines = await _start(Settings(pmac_port="auto"), recorder="R")
        port = started[0].port
        reader, writer = await asyncio.open_connection("127.0.0.1", port)
        writer.write(b"hello\n")
        answer = await reader.readline()
        writer.close()
        started[0].server.close()
        return started, lines, answer

    started, lines, answer = asyncio.run(main())
    assert answer == b"HELLO\n"
    assert lines == [f"motionsim listening fake://127.0.0.1:{started[0].port} (controller pmac)"]
    assert fake_adapter[1][0][3] == {"recorder": "R", "limits": L.ConnectionLimits(32, 600.0)}


def test_zero_disables_the_listener(fake_adapter):
    started, lines = asyncio.run(_start(Settings(pmac_port=0)))
    assert started == [] and lines == [] and fake_adapter[1] == []


def test_a_default_port_that_cannot_be_bound_is_skipped_with_one_line(fake_adapter, monkeypatch):
    sock, port = _busy_port()
    monkeypatch.setattr(L, "PROTOCOLS", (fake_adapter[0].__class__(
        "fake", "fake_adapter_server", "serve_fake", port, "pmac_port", "pmac_controller"),))
    try:
        started, lines = asyncio.run(_start(Settings(pmac_port=None)))
    finally:
        sock.close()
    assert started == []
    assert len(lines) == 1 and lines[0].startswith(f"motionsim skipped fake listener on "
                                                   f"127.0.0.1:{port}: cannot listen")


def test_an_explicit_port_that_cannot_be_bound_is_an_error(fake_adapter):
    sock, port = _busy_port()
    try:
        with pytest.raises(L.ListenerError, match=str(port)):
            asyncio.run(_start(Settings(pmac_port=port)))
    finally:
        sock.close()


def test_missing_controller_or_adapter(fake_adapter, monkeypatch):
    started, lines = asyncio.run(_start(Settings(pmac_port=None, pmac_controller="nope")))
    assert started == [] and "no controller 'nope'" in lines[0]
    monkeypatch.setattr(L, "PROTOCOLS", (L.Protocol("fake", "no_such_adapter_mod", "serve", 0,
                                                    "pmac_port", "pmac_controller"),))
    started, lines = asyncio.run(_start(Settings(pmac_port=None)))
    assert "no_such_adapter_mod is not installed" in lines[0]
    with pytest.raises(L.ListenerError):
        asyncio.run(_start(Settings(pmac_port="auto")))


def test_modbus_listener_is_off_by_default_and_served_when_asked():
    """The Trio Modbus TCP slave starts only with ``modbus_port``; it serves VR() registers."""

    async def main():
        reg = Registry()
        handle = reg.add("trio", "trio", clock="virtual")
        off = await L.start_listeners(reg, Settings(pmac_port=0, trio_port=0), out=lambda _: None)
        lines: list[str] = []
        on = await L.start_listeners(
            reg, Settings(pmac_port=0, trio_port=0, modbus_port="auto"), out=lines.append
        )
        handle.controller.set_variable("VR(3)", 42.0)
        reader, writer = await asyncio.open_connection("127.0.0.1", on[0].port)
        # MBAP: transaction 1, protocol 0, length 6, unit 1; FC 3 read 1 register from 3
        writer.write(bytes([0, 1, 0, 0, 0, 6, 1, 3, 0, 3, 0, 1]))
        await writer.drain()
        answer = await asyncio.wait_for(reader.readexactly(11), 5)
        writer.close()
        for listener in on:
            listener.server.close()
        await reg.close()
        return off, on, lines, answer

    off, on, lines, answer = asyncio.run(main())
    assert off == []
    assert [(x.protocol, x.controller) for x in on] == [("modbus", "trio")]
    assert lines == [f"motionsim listening modbus://127.0.0.1:{on[0].port} (controller trio)"]
    assert answer[7:] == bytes([3, 2, 0, 42])
