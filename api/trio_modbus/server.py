"""The Trio Modbus TCP slave: connections ↔ :mod:`motionsim.api.trio_modbus.protocol` ↔ ``VR()``
and the digital I/O.

Register reads come from ``controller.get_variable("VR(n)")`` (``"TABLE(n)"`` after
``ETHERNET(2, slot, 9, 1)``: ``TrioController.modbus_registers``; the register numbers
mapped stay those of the VR range, ``[INF]``); coil reads (FC 1) from
``OP(n)`` (the output state, as ``READ_OP(n)`` reads it); discrete-input reads (FC 2) from the
inputs as a program's ``IN(n)`` reads them (INVERT_IN applied). Writes go through
``handle.apply(controller.set_variable, "VR(n)" / "OP(n)", value)`` at the current simulated
instant, so a BASIC program waiting on ``VR(n)`` or an output sees a host's write exactly like
one over REST (a coil that changes logs an ``output`` event).
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
from typing import Any

from ...sim.errors import MotionSimError, NotFound
from ...sim.trio import CHANNELS, PATTERN_FIRST
from ..wire import (
    FAIR_SHARE,
    close_when_deleted,
    current_handle,
    default_limits,
    read_chunk,
    start_server,
)
from .protocol import (
    ILLEGAL_ADDRESS,
    NEED_DATA,
    ModbusCodec,
    ProtocolError,
    ReadBits,
    ReadRegisters,
    Rejected,
    WriteCoils,
    WriteRegisters,
    to_register,
)

log = logging.getLogger("motionsim.trio_modbus")


def answer(handle: Any, codec: ModbusCodec, request: Any) -> bytes:
    """The bytes answering one request (writes applied first)."""
    ctl = handle.controller
    registers = ctl.modbus_registers() if hasattr(ctl, "modbus_registers") else "VR"
    try:
        if isinstance(request, Rejected):
            return codec.exception_reply(request)
        if isinstance(request, ReadBits):
            return codec.bits_reply(request, read_bits(ctl, request))
        if isinstance(request, WriteCoils):
            for i, v in enumerate(request.values):
                handle.apply(ctl.set_variable, f"OP({request.start + i})", float(v))
            return codec.coils_reply(request)
        if isinstance(request, WriteRegisters) or request.values:
            start = request.start if isinstance(request, WriteRegisters) else request.write_start
            for i, v in enumerate(request.values):
                handle.apply(ctl.set_variable, f"{registers}({start + i})", float(v))
            if isinstance(request, WriteRegisters):
                return codec.write_reply(request)
        assert isinstance(request, ReadRegisters)
        regs = [to_register(ctl.get_variable(f"{registers}({request.start + i})"))
                for i in range(request.count)]
        return codec.read_reply(request, regs)
    except MotionSimError:
        return codec.exception_reply(
            Rejected(request.transaction, request.unit, request.function, ILLEGAL_ADDRESS))


def read_bits(ctl: Any, request: ReadBits) -> list[int]:
    """FC 1: the outputs' states; FC 2: the inputs as ``IN(n)`` reads them."""
    channels = range(request.start, request.start + request.count)
    if request.function == 1:
        return [1 if ctl.get_variable(f"OP({n})") else 0 for n in channels]
    return [ctl.io.input(n) for n in channels]


async def _serve_connection(handle: Any, reader: asyncio.StreamReader,
                            writer: asyncio.StreamWriter, max_register: int,
                            limits: Any) -> None:
    """Answer requests in order; reading waits for each batch's answers to be sent (so a master
    pipelining without reading is held back), a silent master is dropped after the idle
    timeout, and the connection is closed when the controller is deleted.

    Bounded work per turn: after :data:`~motionsim.api.wire.FAIR_SHARE` answers the
    connection waits for its replies to drain (TCP back-pressure: a master that never reads
    stops being served, not everyone else) and gives the event loop a turn, so one chunk of
    thousands of pipelined FC3 reads cannot starve the PMAC and Trio ports or ``/health``."""
    codec = ModbusCodec(max_register, max_bit=CHANNELS - 1, first_output=PATTERN_FIRST)
    unsubscribe = close_when_deleted(handle, writer)
    try:
        while data := await read_chunk(reader, limits):
            codec.receive_data(data)
            served = 0
            while (request := codec.next_request()) is not NEED_DATA:
                writer.write(answer(handle, codec, request))
                served += 1
                if served % FAIR_SHARE == 0:
                    await writer.drain()
                    await asyncio.sleep(0)  # everyone else's turn
            await writer.drain()
    except ProtocolError as exc:
        log.warning("Modbus TCP: %s; closing the connection", exc)
    except (ConnectionError, OSError):
        pass
    finally:
        unsubscribe()
        writer.close()
        with contextlib.suppress(Exception):
            await writer.wait_closed()


async def serve_modbus(handle: Any, host: str = "127.0.0.1", port: int = 502, *,
                       max_register: int = 1023, limits: Any = None,
                       **_: Any) -> asyncio.Server:
    """Listen for Modbus TCP masters on ``handle``'s Trio (``port=0`` picks one); ``handle``
    and ``limits`` as for :func:`motionsim.api.pmac_ethernet.server.serve_pmac`."""
    limits = limits if limits is not None else default_limits()

    async def connect(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        try:
            current = current_handle(handle)
        except NotFound:
            writer.close()
            return
        await _serve_connection(current, reader, writer, max_register, limits)

    return await start_server(connect, host, port, limits)


__all__ = ["answer", "read_bits", "serve_modbus"]
