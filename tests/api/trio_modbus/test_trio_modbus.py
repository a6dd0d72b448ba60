"""The Trio Modbus TCP slave: holding registers are VR() as int16 (spec trio.md §0.12, §3.3),
driven by a pymodbus client over loopback and by raw frames for the exception answers."""

from __future__ import annotations

import struct

import pytest
from motionsim.api.trio_modbus.protocol import (
    NEED_DATA,
    ModbusCodec,
    ProtocolError,
    ReadBits,
    ReadRegisters,
    Rejected,
    WriteCoils,
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
        (b"\x04\x00\x00\x00\x08", 1),          # read input registers: not in Trio's table
        (b"\x01\x00\xf8\x00\x09", 2),          # coils 248..256: beyond channel 255
        (b"\x02\x00\x00\x00\x00", 3),          # zero inputs
        (b"\x05\x00\x03\xff\x00", 2),          # coil 3: channels 0..7 are inputs (M216-523)
        (b"\x05\x00\x09\x12\x34", 3),          # coil value neither FF00 nor 0000
        (b"\x0f\x00\x08\x00\x09\x01\xff", 3),  # 9 coils need 2 bytes, not 1
        (b"\x0f\x00\xfe\x00\x03\x01\x07", 2),  # coils 254..256
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


def test_coil_and_input_requests_decode_and_answer_packed_lsb_first() -> None:
    """Modbus application protocol framing of FC 1 / 2 / 5 / 15 (bits LSB first, FC 5 echoed,
    FC 15 answers start and quantity); Trio maps them to its I/O (M216-522/523)."""
    codec = ModbusCodec()
    codec.receive_data(mb(1, b"\x01\x00\x08\x00\x0a") + mb(2, b"\x05\x00\x09\xff\x00")
                       + mb(3, b"\x0f\x00\x10\x00\x0a\x02\x0d\x02"))
    read, one, many = codec.next_request(), codec.next_request(), codec.next_request()
    assert read == ReadBits(1, 1, 1, 8, 10)
    assert one == WriteCoils(2, 1, 5, 9, (1,))
    assert many == WriteCoils(3, 1, 15, 16, (1, 0, 1, 1, 0, 0, 0, 0, 0, 1))
    assert codec.bits_reply(read, [1, 0, 0, 0, 0, 0, 0, 1, 1, 0]) == mb(1, b"\x01\x02\x81\x01")
    assert codec.coils_reply(one) == mb(2, b"\x05\x00\x09\xff\x00")
    assert codec.coils_reply(many) == mb(3, b"\x0f\x00\x10\x00\x0a")


def test_pymodbus_reads_inputs_and_outputs_and_switches_outputs() -> None:
    """Trio "MODBUS TCP/IP": 1 and 2 read the Trio I/O, 5 writes a Trio output (15 the same
    for a block, [INF]); a coil write is an OP(n, ON/OFF) at the current instant and logs an
    ``output`` event."""
    from pymodbus.client import AsyncModbusTcpClient

    async def scenario(handle, port):
        ctl = handle.controller
        ctl.set_variable("IN(2)", 1.0)
        ctl.set_variable("IN(5)", 1.0)
        ctl.io.invert(5, True)  # INVERT_IN(5, ON): the program reads input 5 as OFF
        ctl.io.invert(6, True)  # ... and input 6 as ON
        ctl.set_variable("OP(9)", 1.0)
        client = AsyncModbusTcpClient("127.0.0.1", port=port)
        await client.connect()
        inputs = await client.read_discrete_inputs(0, count=8)
        coils = await client.read_coils(8, count=4)
        await client.write_coil(12, True)
        await client.write_coils(16, [True, False, True])
        await client.write_coil(9, False)
        low = await client.write_coil(3, True)
        client.close()
        ops = {n: ctl.get_variable(f"OP({n})") for n in (9, 12, 16, 17, 18)}
        events = [(e.t, e["output"], e["value"]) for e in ctl.log.events("output")]
        return inputs.bits[:8], coils.bits[:4], ops, low.isError(), events

    inputs, coils, ops, low_is_error, events = run_served(serve_modbus, "trio", "trio", scenario)
    assert inputs == [False, False, True, False, False, False, True, False]
    assert coils == [False, True, False, False]
    assert ops == {9: 0.0, 12: 1.0, 16: 1.0, 17: 0.0, 18: 1.0}
    assert low_is_error  # FC 5 starting address range 8..NIO-1 (M216-523)
    assert events == [(0, 9, 1), (0, 12, 1), (0, 16, 1), (0, 18, 1), (0, 9, 0)]


def test_ethernet_2_9_1_maps_holding_registers_to_table_where_scope_samples_are() -> None:
    """Spec trio.md §3.3 (M224-550): ``ETHERNET(2, slot, 9, 1)`` makes the holding registers
    TABLE instead of VR; a SCOPE capture's samples (TABLE entries) are then read over Modbus
    (issue 34)."""
    from pymodbus.client import AsyncModbusTcpClient

    async def scenario(handle, port):
        ctl = handle.controller
        for line in ("VR(3)=7", "TABLE(5)=99", "ETHERNET(2,-1,9,1)",
                     "SCOPE(ON, 1, 10, 14, VR(3))", "TRIGGER"):
            assert handle.apply(ctl.terminal, line).error is None
        await handle.advance(0.01)
        client = AsyncModbusTcpClient("127.0.0.1", port=port)
        await client.connect()
        table = await client.read_holding_registers(10, count=4)
        five = await client.read_holding_registers(5, count=1)
        await client.write_register(20, 42)
        client.close()
        return table.registers, five.registers, ctl.get_variable("TABLE(20)"), \
            ctl.get_variable("VR(20)")

    table, five, written, vr = run_served(serve_modbus, "trio", "trio", scenario)
    assert table == [7, 7, 7, 7] and five == [99]
    assert (written, vr) == (42.0, 0.0)
