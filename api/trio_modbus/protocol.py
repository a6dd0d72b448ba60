"""Sans-I/O codec of the Trio Motion Coordinator's Modbus TCP slave (spec trio.md §0.12, §3.3).

The Motion Coordinator (P296 Ethernet on MC2xx, built in on MC4xx) is a Modbus TCP slave on
port 502: holding registers are the global ``VR()`` variables, register n = ``VR(n)``
(MODICON 40001 + n), transferred as 16-bit signed integers by default; the coil and input
status functions read and write the controller's digital I/O (Trio's "MODBUS TCP/IP" product
page: 1 and 2 "reads Trio IO", 5 "write to a Trio Output"; the TRM's Modbus code table,
M216-522/523: 1 and 2 return the input/output bit pattern, channel n = bit address n, 5 sets
``OP(n, ON/OFF)`` for n = 8..NIO-1). Functions served:

* 1  read coils (1..2000)                  → outputs ``OP(start)`` .. (``READ_OP``), one bit each
* 2  read discrete inputs (1..2000)        → inputs ``IN(start)`` .. as the program reads them
* 3  read holding registers (1..125)       → ``VR(start)`` .. as int16
* 5  write single coil                     → ``OP(n, ON)`` (FF00) / ``OP(n, OFF)`` (0000)
* 6  write single register                 → ``VR(n) = value`` (int16)
* 15 write multiple coils (1..1968)        → ``OP(start..)`` ``[INF]`` (not in Trio's table;
  served as 5 repeated, for HMIs that write their buttons in blocks)
* 16 write multiple registers (1..123)     → ``VR(start..)``
* 23 read/write multiple registers         (writes first, then reads, as the standard says)

Bit addresses are I/O channel numbers, ``0..max_bit`` (the simulator's 256 channels); a coil
write below ``first_output`` (8: channels 0..7 are inputs only on the boards documented) is
refused like one beyond the map. ``[INF]``: the TRM says 1 and 2 both return "the input/output
bit pattern" (on the boards channels 8.. are bidirectional, so IN(n) sees an output that is
on); the simulator keeps inputs and outputs apart, so coils (1) are the outputs and discrete
inputs (2) the inputs, which is what an HMI's lamps (coils it wrote) and status fields expect.

Anything else answers exception 01 (illegal function); registers or bits outside the map
exception 02 (illegal data address); a bad count, byte count or coil value (5: neither FF00
nor 0000) exception 03 (illegal data value).

Inferred (``[INF]``): a VR holding a fraction or a value outside int16 is truncated toward
zero and saturated to -32768..32767 when read as a register (the manuals found do not say);
the 32-bit float and TABLE modes (``ETHERNET(2,slot,7,1)`` / ``(…,9,1)``) are not modelled.

Framing: MBAP header (transaction id u16, protocol id u16 = 0, length u16 = unit id + PDU,
unit id u8) then the PDU (function code u8 + data), all big-endian. A length outside 2..254
or a protocol id other than 0 breaks the stream (:class:`ProtocolError`: close it).
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from typing import Final

from ..wire import NEED_DATA, NeedData, ProtocolError

MBAP: Final = struct.Struct(">HHHB")
MAX_READ: Final = 125
MAX_WRITE: Final = 123
#: Modbus application protocol: bits per read (1, 2) and per write (15).
MAX_READ_BITS: Final = 2000
MAX_WRITE_BITS: Final = 1968
COIL_ON, COIL_OFF = 0xFF00, 0x0000

ILLEGAL_FUNCTION, ILLEGAL_ADDRESS, ILLEGAL_VALUE = 1, 2, 3


@dataclass(frozen=True, slots=True)
class ReadRegisters:
    """Read ``count`` holding registers from ``start`` (FC 3), then optionally written first
    (FC 23: ``write_start``/``values``)."""

    transaction: int
    unit: int
    function: int
    start: int
    count: int
    write_start: int = 0
    values: tuple[int, ...] = ()


@dataclass(frozen=True, slots=True)
class WriteRegisters:
    """Write ``values`` from ``start`` (FC 6 or 16)."""

    transaction: int
    unit: int
    function: int
    start: int
    values: tuple[int, ...]


@dataclass(frozen=True, slots=True)
class ReadBits:
    """Read ``count`` coils (FC 1: outputs) or discrete inputs (FC 2: inputs) from ``start``."""

    transaction: int
    unit: int
    function: int
    start: int
    count: int


@dataclass(frozen=True, slots=True)
class WriteCoils:
    """Switch outputs ``start``.. to ``values`` (1 = ON, 0 = OFF) (FC 5 or 15)."""

    transaction: int
    unit: int
    function: int
    start: int
    values: tuple[int, ...]


@dataclass(frozen=True, slots=True)
class Rejected:
    """A well-framed request the slave answers with an exception code."""

    transaction: int
    unit: int
    function: int
    exception: int


ModbusRequest = ReadRegisters | WriteRegisters | ReadBits | WriteCoils | Rejected


def to_register(value: float) -> int:
    """A VR value as the int16 register the host reads ``[INF]`` (truncate, saturate)."""
    n = int(value) if value == value else 0  # NaN → 0
    return max(-32768, min(32767, n))


class ModbusCodec:
    """One Modbus TCP connection: bytes in → requests; answers → bytes.

    Args:
        max_register: the highest VR number mapped (TJ1 VR(0)..VR(1023); default 1023).
        max_bit: the highest I/O channel mapped to a coil / discrete input (default 255).
        first_output: the lowest channel a coil write may switch (default 8, M216-523).
    """

    def __init__(self, max_register: int = 1023, max_bit: int = 255,
                 first_output: int = 8) -> None:
        self.max_register = max_register
        self.max_bit = max_bit
        self.first_output = first_output
        self._buf = bytearray()

    def receive_data(self, data: bytes) -> None:
        self._buf += data

    def next_request(self) -> ModbusRequest | NeedData:
        if len(self._buf) < MBAP.size:
            return NEED_DATA
        tid, pid, length, unit = MBAP.unpack_from(self._buf)
        if pid != 0 or not 2 <= length <= 254:
            raise ProtocolError(f"bad MBAP header (protocol id {pid}, length {length})")
        end = 6 + length
        if len(self._buf) < end:
            return NEED_DATA
        pdu = bytes(self._buf[MBAP.size:end])
        del self._buf[:end]
        return self._decode(tid, unit, pdu)

    def _decode(self, tid: int, unit: int, pdu: bytes) -> ModbusRequest:
        fc = pdu[0]
        data = pdu[1:]

        def reject(code: int) -> Rejected:
            return Rejected(tid, unit, fc, code)

        try:
            if fc in (1, 2):
                start, count = struct.unpack(">HH", data[:4])
                if not 1 <= count <= MAX_READ_BITS or len(data) != 4:
                    return reject(ILLEGAL_VALUE)
                if start + count - 1 > self.max_bit:
                    return reject(ILLEGAL_ADDRESS)
                return ReadBits(tid, unit, fc, start, count)
            if fc == 5:
                start, raw = struct.unpack(">HH", data[:4])
                if len(data) != 4 or raw not in (COIL_ON, COIL_OFF):
                    return reject(ILLEGAL_VALUE)
                if not self.first_output <= start <= self.max_bit:
                    return reject(ILLEGAL_ADDRESS)
                return WriteCoils(tid, unit, fc, start, (1 if raw == COIL_ON else 0,))
            if fc == 15:
                start, count, nbytes = struct.unpack(">HHB", data[:5])
                if (not 1 <= count <= MAX_WRITE_BITS or nbytes != (count + 7) // 8
                        or len(data) != 5 + nbytes):
                    return reject(ILLEGAL_VALUE)
                if start < self.first_output or start + count - 1 > self.max_bit:
                    return reject(ILLEGAL_ADDRESS)
                packed = data[5:]
                bits = tuple((packed[i // 8] >> (i % 8)) & 1 for i in range(count))
                return WriteCoils(tid, unit, fc, start, bits)
            if fc == 3:
                start, count = struct.unpack(">HH", data[:4])
                if not 1 <= count <= MAX_READ or len(data) != 4:
                    return reject(ILLEGAL_VALUE)
                if start + count - 1 > self.max_register:
                    return reject(ILLEGAL_ADDRESS)
                return ReadRegisters(tid, unit, fc, start, count)
            if fc == 6:
                start, raw = struct.unpack(">Hh", data[:4])
                if len(data) != 4:
                    return reject(ILLEGAL_VALUE)
                if start > self.max_register:
                    return reject(ILLEGAL_ADDRESS)
                return WriteRegisters(tid, unit, fc, start, (raw,))
            if fc == 16:
                start, count, nbytes = struct.unpack(">HHB", data[:5])
                if not 1 <= count <= MAX_WRITE or nbytes != 2 * count or len(data) != 5 + nbytes:
                    return reject(ILLEGAL_VALUE)
                if start + count - 1 > self.max_register:
                    return reject(ILLEGAL_ADDRESS)
                values = struct.unpack(f">{count}h", data[5:])
                return WriteRegisters(tid, unit, fc, start, values)
            if fc == 23:
                rstart, rcount, wstart, wcount, nbytes = struct.unpack(">HHHHB", data[:9])
                if (not 1 <= rcount <= MAX_READ or not 1 <= wcount <= 121
                        or nbytes != 2 * wcount or len(data) != 9 + nbytes):
                    return reject(ILLEGAL_VALUE)
                if (rstart + rcount - 1 > self.max_register
                        or wstart + wcount - 1 > self.max_register):
                    return reject(ILLEGAL_ADDRESS)
                values = struct.unpack(f">{wcount}h", data[9:])
                return ReadRegisters(tid, unit, fc, rstart, rcount, wstart, values)
        except struct.error:
            return reject(ILLEGAL_VALUE)
        return reject(ILLEGAL_FUNCTION)

    @staticmethod
    def _frame(tid: int, unit: int, pdu: bytes) -> bytes:
        return MBAP.pack(tid, 0, len(pdu) + 1, unit) + pdu

    def read_reply(self, request: ReadRegisters, registers: list[int]) -> bytes:
        body = struct.pack(f">{len(registers)}h", *registers)
        pdu = bytes([request.function, len(body)]) + body
        return self._frame(request.transaction, request.unit, pdu)

    def write_reply(self, request: WriteRegisters) -> bytes:
        if request.function == 6:
            pdu = struct.pack(">BHh", 6, request.start, request.values[0])
        else:
            pdu = struct.pack(">BHH", 16, request.start, len(request.values))
        return self._frame(request.transaction, request.unit, pdu)

    def bits_reply(self, request: ReadBits, bits: list[int]) -> bytes:
        """FC 1 / 2: the byte count, then the bits packed LSB first (bit 0 = ``start``)."""
        packed = bytearray((len(bits) + 7) // 8)
        for i, b in enumerate(bits):
            if b:
                packed[i // 8] |= 1 << (i % 8)
        pdu = bytes([request.function, len(packed)]) + bytes(packed)
        return self._frame(request.transaction, request.unit, pdu)

    def coils_reply(self, request: WriteCoils) -> bytes:
        """FC 5 echoes the request; FC 15 answers the start and how many were written."""
        if request.function == 5:
            raw = COIL_ON if request.values[0] else COIL_OFF
            pdu = struct.pack(">BHH", 5, request.start, raw)
        else:
            pdu = struct.pack(">BHH", 15, request.start, len(request.values))
        return self._frame(request.transaction, request.unit, pdu)

    def exception_reply(self, request: Rejected) -> bytes:
        pdu = bytes([(request.function | 0x80) & 0xFF, request.exception])
        return self._frame(request.transaction, request.unit, pdu)


__all__ = ["NEED_DATA", "ModbusCodec", "ProtocolError", "ReadBits", "ReadRegisters",
           "Rejected", "WriteCoils", "WriteRegisters", "to_register"]
