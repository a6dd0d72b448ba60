"""The Trio Modbus TCP slave: connections ↔ :mod:`motionsim.api.trio_modbus.protocol` ↔ ``VR()``.

Reads come from ``controller.get_variable("VR(n)")``; writes go through
``handle.apply(controller.set_variable, "VR(n)", value)`` at the current simulated instant,
so a BASIC program waiting on ``VR(n)`` sees a host's write exactly like one over REST.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
from typing import Any

from motionsim.api.trio_modbus.protocol import (
    ILLEGAL_ADDRESS,
    NEED_DATA,
    ModbusCodec,
    ProtocolError,
    ReadRegisters,
    Rejected,
    WriteRegisters,
    to_register,
)
from motionsim.api.wire import start_server
from motionsim.sim.errors import MotionSimError

log = logging.getLogger("motionsim.trio_modbus")


def answer(handle: Any, codec: ModbusCodec, request: Any) -> bytes:
    """The bytes answering one request (writes applied first)."""
    ctl = handle.controller
    try:
        if isinstance(request, Rejected):
            return codec.exception_reply(request)
        if isinstance(request, WriteRegisters) or request.values:
            start = request.start if isinstance(request, WriteRegisters) else request.write_start
            for i, v in enumerate(request.values):
                handle.apply(ctl.set_variable, f"VR({start + i})", float(v))
            if isinstance(request, WriteRegisters):
                return codec.write_reply(request)
        assert isinstance(request, ReadRegisters)
        regs = [to_register(ctl.get_variable(f"VR({request.start + i})"))
                for i in range(request.count)]
        return codec.read_reply(request, regs)
    except MotionSimError:
        return codec.exception_reply(
            Rejected(request.transaction, request.unit, request.function, ILLEGAL_ADDRESS))


async def _serve_connection(handle: Any, reader: asyncio.StreamReader,
                            writer: asyncio.StreamWriter, max_register: int) -> None:
    codec = ModbusCodec(max_register)
    try:
        while data := await reader.read(65536):
            codec.receive_data(data)
            while (request := codec.next_request()) is not NEED_DATA:
                writer.write(answer(handle, codec, request))
            await writer.drain()
    except ProtocolError as exc:
        log.warning("Modbus TCP: %s; closing the connection", exc)
    except (ConnectionError, OSError):
        pass
    finally:
        writer.close()
        with contextlib.suppress(Exception):
            await writer.wait_closed()


async def serve_modbus(handle: Any, host: str = "127.0.0.1", port: int = 502, *,
                       max_register: int = 1023, **_: Any) -> asyncio.Server:
    """Listen for Modbus TCP masters on ``handle``'s Trio (``port=0`` picks one)."""

    async def connect(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        await _serve_connection(handle, reader, writer, max_register)

    return await start_server(connect, host, port)


__all__ = ["answer", "serve_modbus"]
