"""The Trio Modbus TCP slave: holding registers are VR() as int16 (spec trio.md §0.12, §3.3),
driven by a pymodbus client over loopback and by raw frames for the exception answers."""

from __future__ import annotations

import struct

import pytest
from motionsim.api.trio_modbus.protocol import (
    NEED_DATA,
    ModbusCodec,
    ProtocolError,
    ReadRegisters,
    Rejected,
    to_register,
)
from motionsim.api.trio_modbus.server import serve_modbus

from tests.api.wire_helpers import run_served


def run(scenario):
    return run_served(serve_modbus, "wiretrio", "trio", scenario)


def test_pymodbus_reads_and_writes_vr_as_holding_registers() -> None:
    from pymodbus.client import AsyncModbusTcpClient

    async def scenario(handle, port):
        handle.controller.set_variable("VR(10)", 255.0)
        handle.controller.set_variable("VR(11)", -3.7)
        client = AsyncModbusTcpClient("127.0.0.1", port=port)
        await client.connect()
        read = await client.read_holding_registers(10, count=3)
        await client.write_register(20, 1234)
        await client.write_registers(30, [1, 2, 65535])
        bad = await client.read_holding_registers(1020, count=10)
        client.close()
        vr = {n: handle.controller.get_variable(f"VR({n})") for n in (20, 30, 31, 32)}
        writes = [(e.t, e["index"], e["value"]) for e in handle.controller.log.events("vr")]
        return read.registers, vr, bad.isError(), writes

    regs, vr, bad_is_error, writes = run(scenario)
    assert regs == [255, 65533, 0]  # -3 as an unsigned 16-bit register
    assert vr == {20: 1234.0, 30: 1.0, 31: 2.0, 32: -1.0}
    assert bad_is_error
    assert writes[-4:] == [(0, 20, 1234.0), (0, 30, 1.0), (0, 31, 2.0), (0, 32, -1.0)]


def mb(tid: int, pdu: bytes, unit: int = 1) -> bytes:
    return struct.pack(">HHHB", tid, 0, len(pdu) + 1, unit) + pdu


@pytest.mark.parametrize(
    ("pdu", "exception"),
    [
        (b"\x01\x00\x00\x00\x08", 1),          # read coils: not served
        (b"\x03\x03\xff\x00\x02", 2),          # VR(1023), VR(1024): beyond the map
        (b"\x03\x00\x00\x00\x00", 3),          # zero registers
        (b"\x10\x00\x00\x00\x02\x02\x00\x01", 3),  # byte count does not match
    ],
)
def test_bad_requests_answer_modbus_exceptions(pdu: bytes, exception: int) -> None:
    codec = ModbusCodec()
    codec.receive_data(mb(7, pdu))
    req = codec.next_request()
    assert isinstance(req, Rejected) and req.exception == exception
    assert codec.exception_reply(req) == mb(7, bytes([pdu[0] | 0x80, exception]))


def test_frames_split_anywhere_and_broken_header_closes() -> None:
    codec = ModbusCodec()
    frame = mb(1, b"\x03\x00\x05\x00\x02")
    for b in frame[:-1]:
        codec.receive_data(bytes([b]))
        assert codec.next_request() is NEED_DATA
    codec.receive_data(frame[-1:])
    assert codec.next_request() == ReadRegisters(1, 1, 3, 5, 2)
    codec.receive_data(struct.pack(">HHHB", 1, 7, 6, 1))
    with pytest.raises(ProtocolError):
        codec.next_request()


def test_vr_values_become_int16_registers() -> None:
    assert [to_register(v) for v in (2.9, -2.9, 40000, -40000, float("nan"))] == [
        2, -2, 32767, -32768, 0]
