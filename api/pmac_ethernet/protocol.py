"""Sans-I/O codec of the Turbo PMAC Ethernet protocol (ACC-54E / UMAC CPU / Geo Brick, TCP 1025).

No sockets, no asyncio, no controller here (like h11): bytes in → typed requests out, and
controller answers in → reply bytes out. ``server.py`` owns the socket and the controller calls.

The wire (spec pmac.md §5.1): every request starts with an 8-byte header ::

    RequestType u8 | Request u8 | wValue u16 | wIndex u16 | wLength u16      (u16 big-endian)

``RequestType`` is 0x40 (VR_DOWNLOAD, host → PMAC) or 0xC0 (VR_UPLOAD, PMAC → host). A payload
of ``wLength`` bytes follows only a *download* request that carries data (GETRESPONSE,
SENDLINE, WRITEBUFFER, SETMEM, SETBIT(S), FWDOWNLOAD, IPADDRESS-set); for the other requests
``wLength`` is the reply size wanted and nothing follows. The stream is read as header + payload,
never as one ``recv()`` per packet.

Replies to ASCII commands are framed by I3 (handshake) and I6 (error report) exactly as the
PMAC's own serial port frames them (spec §2): with the I3=2 / I6=1 that the DLS clients set,
each data line ends ``\\r``, the whole reply ends with one ``\\x06`` (ACK), and an error is
``\\x07ERRnnn\\r`` with no ACK. The PMAC keeps the ASCII output of each host port in a queue:

* one *response* per command line (its data lines and its terminator) is appended to the
  queue of the connection that sent the line;
* VR_PMAC_GETRESPONSE executes its line(s) and returns the queue's first response — up to
  the ACK, or up to the CR after a BELL — at most 1400 bytes; the rest stays queued and is
  fetched with VR_PMAC_GETBUFFER (what dls-pmaclib does for long replies);
* VR_PMAC_READREADY reports whether anything is queued, VR_PMAC_FLUSH (CTRL-X) empties the
  queue and answers the single byte ``@``.

Inferred (``[INF]``, the manuals found are silent; see spec §5.1 and §7):

* several CR/LF/NUL-separated lines in one GETRESPONSE are several command lines, each with
  its own response in the queue; GETRESPONSE returns only the first (as the firmware returns
  "everything up to ACK"), the others wait for GETBUFFER.
* the single byte answering SENDLINE, SETMEM, SETBIT(S), FWDOWNLOAD and a PORT write is ``@``
  like FLUSH's; an upload that finds nothing queued answers one NUL byte (which dls-pmaclib
  reads as "PMAC busy").
* a 1400-byte piece never ends in ``\\r`` while more of the same response follows: the piece
  takes the next byte too (at most a few bytes over 1400), so a client that reads "ends in
  CR" as "complete" is never left one reply behind.
* WRITEBUFFER's failing line number is the 0-based index of the line in the request; the
  output of lines it executes successfully is discarded.
* a download payload longer than the packet's data area (1492 bytes), an unknown
  RequestType or an unknown Request code closes the connection (:class:`ProtocolError`).
* bytes above 127 in a command line answer ERR004 ("illegal character") and the line is not
  executed.
"""

from __future__ import annotations

import re
import struct
from collections import deque
from collections.abc import Iterable
from dataclasses import dataclass
from enum import IntEnum
from typing import Final

from ..wire import NEED_DATA, NeedData, ProtocolError

#: Header layout: RequestType, Request, wValue, wIndex, wLength — 16-bit fields big-endian.
HEADER: Final = struct.Struct(">BBHHH")
HEADER_SIZE: Final = HEADER.size  # 8

VR_UPLOAD: Final = 0xC0
VR_DOWNLOAD: Final = 0x40

#: Data area of one packet (``bData[1492]`` in the ETHERNETCMD struct).
MAX_PAYLOAD: Final = 1492
#: Most bytes of queued text one GETRESPONSE / GETBUFFER returns.
MAX_REPLY: Final = 1400
#: Longest piece sent: 1400 plus the few terminator bytes carried over (see :meth:`take`).
MAX_PIECE: Final = MAX_REPLY + 4
#: The byte answering FLUSH (observed on hardware) and, ``[INF]``, the other 1-byte acks.
ACK_BYTE: Final = b"@"
#: Answer to an upload that finds nothing queued ``[INF]``.
EMPTY: Final = b"\x00"

ACK: Final = 0x06
BELL: Final = 0x07
CR: Final = 0x0D
LF: Final = 0x0A
STX: Final = 0x02

_ERR_CODE = re.compile(r"ERR\d{3}")


class VR(IntEnum):
    """The Request byte: what the host asks for."""

    PMAC_SENDLINE = 0xB0
    PMAC_GETLINE = 0xB1
    PMAC_FLUSH = 0xB3
    PMAC_GETMEM = 0xB4
    PMAC_SETMEM = 0xB5
    PMAC_SETBIT = 0xBA
    PMAC_SETBITS = 0xBB
    PMAC_PORT = 0xBE
    PMAC_GETRESPONSE = 0xBF
    PMAC_READREADY = 0xC2
    CTRL_RESPONSE = 0xC4
    PMAC_GETBUFFER = 0xC5
    PMAC_WRITEBUFFER = 0xC6
    FWDOWNLOAD = 0xCB
    IPADDRESS = 0xE0


#: The Request byte's value -> its VR (``VR(code)`` without the enum's call per request).
_VR_OF: Final = {int(v): v for v in VR}

#: Requests followed by a ``wLength``-byte payload when sent as VR_DOWNLOAD.
_CARRIES_DATA: Final = frozenset(
    {
        VR.PMAC_SENDLINE,
        VR.PMAC_GETRESPONSE,
        VR.PMAC_WRITEBUFFER,
        VR.PMAC_SETMEM,
        VR.PMAC_SETBIT,
        VR.PMAC_SETBITS,
        VR.FWDOWNLOAD,
        VR.IPADDRESS,
    }
)
#: Requests that only make sense as downloads (the host sends text or data).
_DOWNLOAD_ONLY: Final = frozenset(
    {VR.PMAC_SENDLINE, VR.PMAC_GETRESPONSE, VR.PMAC_WRITEBUFFER, VR.PMAC_SETMEM,
     VR.PMAC_SETBIT, VR.PMAC_SETBITS, VR.FWDOWNLOAD}
)


# -- requests (frozen values) ------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Header:
    """The 8-byte header as sent."""

    request_type: int
    request: int
    value: int
    index: int
    length: int

    def pack(self) -> bytes:
        return HEADER.pack(self.request_type, self.request, self.value, self.index, self.length)


@dataclass(frozen=True, slots=True)
class GetResponse:
    """VR_PMAC_GETRESPONSE: execute ``lines``, return the first queued response."""

    lines: tuple[str, ...]


@dataclass(frozen=True, slots=True)
class SendLine:
    """VR_PMAC_SENDLINE: execute ``lines``, queue their output, answer one byte."""

    lines: tuple[str, ...]


@dataclass(frozen=True, slots=True)
class WriteBuffer:
    """VR_PMAC_WRITEBUFFER: a multi-line download (each line NUL-terminated); 4-byte status."""

    lines: tuple[str, ...]


@dataclass(frozen=True, slots=True)
class CtrlResponse:
    """VR_CTRL_RESPONSE: a control character (^B ^C ^F ^G ^P ^V) and its reply."""

    char: int


@dataclass(frozen=True, slots=True)
class PortWrite:
    """VR_PMAC_PORT download: one character written to the host port."""

    char: int


@dataclass(frozen=True, slots=True)
class PortRead:
    """VR_PMAC_PORT upload: read one character of queued output."""


@dataclass(frozen=True, slots=True)
class GetLine:
    """VR_PMAC_GETLINE: queued text up to CR, ACK or LF."""


@dataclass(frozen=True, slots=True)
class GetBuffer:
    """VR_PMAC_GETBUFFER: queued text, same termination as GETRESPONSE, at most ``max_bytes``."""

    max_bytes: int


@dataclass(frozen=True, slots=True)
class ReadReady:
    """VR_PMAC_READREADY: 2 bytes, byte 0 non-zero when output is waiting."""


@dataclass(frozen=True, slots=True)
class Flush:
    """VR_PMAC_FLUSH: CTRL-X to the PMAC (discard queued output); answers ``@``."""

    timeout_ms: int


@dataclass(frozen=True, slots=True)
class Memory:
    """DPRAM and firmware requests (GETMEM, SETMEM, SETBIT(S), FWDOWNLOAD, IPADDRESS).

    The simulator has no dual-ported RAM: writes are acknowledged and forgotten, reads
    return zeros, IPADDRESS reports the configured address.
    """

    request: VR
    upload: bool
    value: int
    length: int
    data: bytes


Request = (
    GetResponse | SendLine | WriteBuffer | CtrlResponse | PortWrite | PortRead | GetLine
    | GetBuffer | ReadReady | Flush | Memory
)

#: Requests whose answer needs the controller to execute command lines.
EXECUTES: Final = (GetResponse, SendLine, WriteBuffer, CtrlResponse, PortWrite)


@dataclass(frozen=True, slots=True)
class Answer:
    """The controller's answer to one command line: data lines and an error code (or None)."""

    lines: tuple[str, ...] = ()
    error: str | None = None

    @classmethod
    def from_reply(cls, reply: str, error: str | None) -> Answer:
        """From a :class:`~motionsim.sim.controller.Reply`'s text (lines joined by CR) and error."""
        lines = tuple(reply.split("\r")) if reply else ()
        if error is not None and not _ERR_CODE.fullmatch(error):
            error = "ERR003"
        return cls(lines, error)


# -- framing ---------------------------------------------------------------------------


def frame(answer: Answer, i3: int = 2, i6: int = 1) -> bytes:
    """One command line's output as the PMAC sends it, per I3 and I6 (spec §2.1, §2.2).

    I3: 0 ``DATA<CR>``, no ack; 1 ``<LF>DATA<CR>…<LF>``; 2 ``DATA<CR>…<ACK>``;
    3 ``<LF>DATA<CR>…<ACK>``. An error replaces the ack: I6=1 ``<BELL>ERRnnn<CR>``,
    I6=3 ``<BELL><CR>ERRnnn<CR>``, I6=0/2 a bare ``<BELL>``; with I3=1/3 an ``<LF>`` precedes it.
    Out-of-range values wrap modulo 4, as the PMAC wraps I-variable values.
    """
    i3 &= 3
    i6 &= 3
    lead = b"\n" if i3 in (1, 3) else b""
    out = bytearray()
    for line in answer.lines:
        out += lead
        out += line.encode("latin-1", "replace")
        out.append(CR)
    if answer.error is not None:
        out += lead
        out.append(BELL)
        code = answer.error.encode("ascii", "replace")
        if i6 == 1:
            out += code + b"\r"
        elif i6 == 3:
            out += b"\r" + code + b"\r"
        return bytes(out)
    if i3 == 1:
        out.append(LF)
    elif i3 >= 2:
        out.append(ACK)
    return bytes(out)


def write_buffer_status(error: str | None = None, line: int = 0) -> bytes:
    """The 4-byte answer to WRITEBUFFER: byte 3 = 0x80 on error, byte 2 = the error number,
    bytes 1:0 = the failing line (MSB in byte 1); all zero when every line was accepted."""
    if error is None:
        return b"\x00\x00\x00\x00"
    number = int(error[3:]) if _ERR_CODE.fullmatch(error) else 3
    return bytes([line & 0xFF, (line >> 8) & 0xFF, number & 0xFF, 0x80])


def illegal_character(line: str) -> int | None:
    """0-based column of the first byte above 127 in ``line`` (ERR004), or None."""
    if line.isascii():
        return None
    for i, ch in enumerate(line):
        if ord(ch) > 127:
            return i
    return None


def split_lines(payload: bytes) -> tuple[str, ...]:
    """Command text → command lines: CR, LF and NUL end a line; a trailing terminator is
    optional and empty lines between terminators are dropped, except that a payload of only
    terminators (the EPICS driver's ``"\\n"`` probe) is one empty command line."""
    text = payload.decode("latin-1")
    parts = _LINE_ENDS.split(text)
    lines = tuple(p for p in parts if p != "")
    return lines if lines else ("",)


_LINE_ENDS = re.compile(r"[\r\n\x00]+")


# -- the connection ----------------------------------------------------------------------


class _Unsolicited(bytearray):
    """A queued program-originated line (``SEND``), not the answer to a host command."""


class PmacEthernetCodec:
    """One TCP connection's protocol state: input framing and the port's output queue.

    Use: ``receive_data(chunk)`` as bytes arrive (``b""`` at end of stream); then call
    ``next_request()`` until it returns :data:`NEED_DATA`. For requests in :data:`EXECUTES`
    the caller runs the command lines (``request.lines``, or the line completed by a
    :class:`PortWrite` — see :meth:`port_write`) on the controller and passes the answers to
    :meth:`reply`; every other request is answered by :meth:`reply` from the queue alone.
    """

    def __init__(self, ip_address: bytes = b"\x7f\x00\x00\x01") -> None:
        self._buf = bytearray()
        self._eof = False
        self._broken: ProtocolError | None = None
        self._queue: deque[bytearray] = deque()
        self._port_line = bytearray()
        self.ip_address = ip_address

    # -- input ---------------------------------------------------------------------------

    def receive_data(self, data: bytes) -> None:
        """Bytes from the host; ``b""`` means the host closed its side."""
        if data:
            self._buf += data
        else:
            self._eof = True

    @property
    def eof(self) -> bool:
        return self._eof

    @property
    def pending_bytes(self) -> int:
        """Bytes received but not yet part of a complete request (a request cut short)."""
        return len(self._buf)

    def next_request(self) -> Request | NeedData:
        """The next complete request, or :data:`NEED_DATA`.

        Raises:
            ProtocolError: the stream cannot be the PMAC protocol (unknown RequestType or
                Request, payload longer than a packet). The codec stays broken.
        """
        if self._broken is not None:
            raise self._broken
        if len(self._buf) < HEADER_SIZE:
            return NEED_DATA
        rtype, code, value, index, length = HEADER.unpack_from(self._buf)
        try:
            request = self._check(rtype, code, length)
        except ProtocolError as exc:
            self._broken = exc
            raise
        upload = rtype == VR_UPLOAD
        has_payload = not upload and request in _CARRIES_DATA
        end = HEADER_SIZE + (length if has_payload else 0)
        if len(self._buf) < end:
            return NEED_DATA
        payload = bytes(self._buf[HEADER_SIZE:end])
        del self._buf[:end]
        return self._decode(request, upload, value, index, length, payload)

    def _check(self, rtype: int, code: int, length: int) -> VR:
        if rtype not in (VR_UPLOAD, VR_DOWNLOAD):
            raise ProtocolError(f"RequestType 0x{rtype:02X} is neither VR_DOWNLOAD nor VR_UPLOAD")
        request = _VR_OF.get(code)
        if request is None:
            raise ProtocolError(f"unknown Request code 0x{code:02X}")
        if rtype == VR_UPLOAD and request in _DOWNLOAD_ONLY:
            raise ProtocolError(f"{request.name} must be sent as VR_DOWNLOAD (0x40)")
        if rtype == VR_DOWNLOAD and request in _CARRIES_DATA and length > MAX_PAYLOAD:
            raise ProtocolError(
                f"{request.name} wLength {length} exceeds the {MAX_PAYLOAD}-byte packet"
            )
        return request

    def _decode(
        self, request: VR, upload: bool, value: int, index: int, length: int, payload: bytes
    ) -> Request:
        if request is VR.PMAC_GETRESPONSE:
            return GetResponse(split_lines(payload))
        if request is VR.PMAC_SENDLINE:
            return SendLine(split_lines(payload))
        if request is VR.PMAC_WRITEBUFFER:
            text = payload.decode("latin-1")
            lines = [ln.strip("\r\n") for ln in text.split("\x00")]
            while lines and lines[-1] == "":
                lines.pop()
            return WriteBuffer(tuple(lines))
        if request is VR.CTRL_RESPONSE:
            # C clients htons() wValue, the EPICS driver does not: take whichever byte is set.
            return CtrlResponse((value & 0xFF) or (value >> 8))
        if request is VR.PMAC_PORT:
            if upload:
                return PortRead()
            return PortWrite((value & 0xFF) or (value >> 8))
        if request is VR.PMAC_GETLINE:
            return GetLine()
        if request is VR.PMAC_GETBUFFER:
            return GetBuffer(length)
        if request is VR.PMAC_READREADY:
            return ReadReady()
        if request is VR.PMAC_FLUSH:
            return Flush(value)
        return Memory(request, upload, value, length, payload)

    # -- output --------------------------------------------------------------------------

    @property
    def output_waiting(self) -> bool:
        """Whether any ASCII output is queued for this port."""
        return bool(self._queue)

    def queue(self, response: bytes) -> None:
        """Append one command line's framed output to the port's queue."""
        if response:
            self._queue.append(bytearray(response))

    def unsolicited(self, line: bytes) -> None:
        """Queue one program-originated line (``SEND``, framed by the controller: no ACK,
        ``<STX>`` first when I64=1) behind what is already queued."""
        if line:
            self._queue.append(_Unsolicited(line))

    def take(self, max_bytes: int = MAX_REPLY) -> bytes:
        """The rest of the queue's first response, at most ``max_bytes``; :data:`EMPTY` if none.

        A program line at the head that starts with ``<STX>`` is returned alone (the
        firmware returns only up to the ``<CR>`` after an STX, spec §5.1); one without STX
        (I64=0) has no terminator of its own, so it is returned together with what follows
        it, up to that response's ACK ``[INF]``.
        """
        if not self._queue:
            return EMPTY
        head = self._queue[0]
        while isinstance(head, _Unsolicited) and STX not in head and len(self._queue) > 1:
            self._queue.popleft()
            nxt = self._queue[0]
            nxt[:0] = head  # prepended in place: the piece keeps the next one's kind
            head = nxt
        n = max(1, min(max_bytes, MAX_REPLY))
        while n < len(head) and head[n - 1] in (CR, ACK) and n < MAX_PIECE:
            # A piece that ends in CR while more of the response follows would read as a
            # complete (error) reply: dls-pmaclib stops there and the rest of the response
            # answers its next command. Carry the terminator over into the piece [INF].
            n += 1
        out = bytes(head[:n])
        del head[:n]
        if not head:
            self._queue.popleft()
        return out

    def _take_line(self) -> bytes:
        if not self._queue:
            return EMPTY
        head = self._queue[0]
        end = len(head)
        for i, b in enumerate(head):
            if b in (CR, ACK, LF):
                end = i + 1
                break
        end = min(end, MAX_REPLY)
        out = bytes(head[:end])
        del head[:end]
        if not head:
            self._queue.popleft()
        return out

    def _take_byte(self) -> bytes:
        if not self._queue:
            return EMPTY
        head = self._queue[0]
        out = bytes(head[:1])
        del head[:1]
        if not head:
            self._queue.popleft()
        return out

    def flush(self) -> None:
        """CTRL-X: discard all queued output and any half-typed PORT line."""
        self._queue.clear()
        self._port_line.clear()

    def port_write(self, char: int) -> str | None:
        """Feed one PORT character; returns the command line when ``char`` is CR or LF."""
        if char in (CR, LF):
            line = self._port_line.decode("latin-1")
            self._port_line.clear()
            return line
        if char == 0x18:  # CTRL-X
            self.flush()
            return None
        if len(self._port_line) < MAX_PAYLOAD:
            self._port_line.append(char)
        return None

    def reply(
        self,
        request: Request,
        answers: Iterable[Answer] = (),
        *,
        i3: int = 2,
        i6: int = 1,
    ) -> bytes:
        """The bytes answering ``request``.

        Args:
            request: as returned by :meth:`next_request`.
            answers: for requests in :data:`EXECUTES`, the controller's answer to each line
                executed, in order (WRITEBUFFER: stop at the first error).
            i3, i6: the controller's I3 and I6 when the answers were produced.
        """
        if isinstance(request, GetResponse):
            for answer in answers:
                self.queue(frame(answer, i3, i6))
            return self.take(MAX_REPLY)
        if isinstance(request, CtrlResponse):
            for answer in answers:
                self.queue(frame(answer, i3, i6))
            return self.take(MAX_REPLY)
        if isinstance(request, (SendLine, PortWrite)):
            for answer in answers:
                self.queue(frame(answer, i3, i6))
            return ACK_BYTE
        if isinstance(request, WriteBuffer):
            for index, answer in enumerate(answers):
                if answer.error is not None:
                    return write_buffer_status(answer.error, index)
            return write_buffer_status()
        if isinstance(request, GetBuffer):
            return self.take(request.max_bytes or MAX_REPLY)
        if isinstance(request, GetLine):
            return self._take_line()
        if isinstance(request, PortRead):
            return self._take_byte()
        if isinstance(request, ReadReady):
            return b"\x01\x00" if self._queue else b"\x00\x00"
        if isinstance(request, Flush):
            self.flush()
            return ACK_BYTE
        if isinstance(request, Memory):
            return self._memory(request)
        raise TypeError(f"not a request: {request!r}")

    def _memory(self, request: Memory) -> bytes:
        if request.request is VR.IPADDRESS:
            return self.ip_address if request.upload else (request.data[:4] or self.ip_address)
        if request.request is VR.PMAC_GETMEM:
            return bytes(max(1, min(request.length, MAX_REPLY)))
        return ACK_BYTE


def pack_request(request_type: int, request: int, value: int = 0, index: int = 0,
                 payload: bytes = b"", length: int | None = None) -> bytes:
    """A request as a client sends it (tests, replay, bench): header + payload."""
    n = len(payload) if length is None else length
    return HEADER.pack(request_type, request, value, index, n) + payload


def getresponse(command: str | bytes) -> bytes:
    """A VR_PMAC_GETRESPONSE packet carrying ``command`` (what dls-pmaclib sends)."""
    data = command.encode("latin-1") if isinstance(command, str) else command
    return pack_request(VR_DOWNLOAD, VR.PMAC_GETRESPONSE, payload=data)


__all__ = [
    "ACK_BYTE",
    "EMPTY",
    "EXECUTES",
    "HEADER_SIZE",
    "MAX_PAYLOAD",
    "MAX_PIECE",
    "MAX_REPLY",
    "NEED_DATA",
    "VR",
    "VR_DOWNLOAD",
    "VR_UPLOAD",
    "Answer",
    "CtrlResponse",
    "Flush",
    "GetBuffer",
    "GetLine",
    "GetResponse",
    "Header",
    "Memory",
    "PmacEthernetCodec",
    "PortRead",
    "PortWrite",
    "ProtocolError",
    "ReadReady",
    "Request",
    "SendLine",
    "WriteBuffer",
    "frame",
    "getresponse",
    "illegal_character",
    "pack_request",
    "split_lines",
    "write_buffer_status",
]
