"""The PMAC Ethernet codec without sockets: headers, framing by I3/I6, the output queue.

Facts: spec pmac.md §0.1–0.5, §2.1–2.2, §5.1–5.3 (ACC-54E request table, dls-pmaclib and
EPICS pmacAsynIPPort wire behaviour).
"""

import struct

import pytest
from motionsim.api.pmac_ethernet.protocol import (
    ACK_BYTE,
    EMPTY,
    MAX_REPLY,
    NEED_DATA,
    VR,
    VR_DOWNLOAD,
    VR_UPLOAD,
    Answer,
    CtrlResponse,
    Flush,
    GetBuffer,
    GetLine,
    GetResponse,
    Memory,
    PmacEthernetCodec,
    PortRead,
    PortWrite,
    ProtocolError,
    ReadReady,
    SendLine,
    WriteBuffer,
    frame,
    getresponse,
    illegal_character,
    pack_request,
    write_buffer_status,
)


def feed(codec: PmacEthernetCodec, data: bytes) -> list:
    codec.receive_data(data)
    out = []
    while (req := codec.next_request()) is not NEED_DATA:
        out.append(req)
    return out


def test_dls_pmaclib_getresponse_packet_decodes_to_its_command() -> None:
    """dls-pmaclib packs ``struct.pack("8B", 0x40, 0xBF, 0, 0, 0, 0, 0, len)`` + ASCII."""
    cmd = "i6=1 i3=2 ver"
    packet = struct.pack("8B", 0x40, 0xBF, 0, 0, 0, 0, 0, len(cmd)) + cmd.encode()
    assert feed(PmacEthernetCodec(), packet) == [GetResponse(("i6=1 i3=2 ver",))]


def test_epics_getresponse_with_newline_terminator_and_empty_probe() -> None:
    """The EPICS driver appends ``\\n`` and probes the link with an empty command."""
    codec = PmacEthernetCodec()
    got = feed(codec, getresponse("#1P #1F i124\n") + getresponse("\n"))
    assert got == [GetResponse(("#1P #1F i124",)), GetResponse(("",))]


def test_header_fields_are_big_endian_and_payload_may_arrive_byte_by_byte() -> None:
    codec = PmacEthernetCodec()
    packet = pack_request(VR_DOWNLOAD, VR.PMAC_GETRESPONSE, payload=b"x" * 300)
    assert packet[6:8] == b"\x01\x2c"
    for b in packet[:-1]:
        assert feed(codec, bytes([b])) == []
    assert feed(codec, packet[-1:]) == [GetResponse(("x" * 300,))]


def test_upload_requests_carry_no_payload() -> None:
    """READREADY sends wLength=2 and GETBUFFER wLength=0x0800 with nothing after the header."""
    codec = PmacEthernetCodec()
    stream = (
        bytes.fromhex("c0c2000000000002")
        + bytes.fromhex("c0c5000000000800")
        + bytes.fromhex("c0b1000000000000")
        + bytes.fromhex("40b3000a00000000")
    )
    assert feed(codec, stream) == [ReadReady(), GetBuffer(2048), GetLine(), Flush(10)]


@pytest.mark.parametrize(
    ("i3", "i6", "answer", "wire"),
    [
        (2, 1, Answer(("1.947  ",)), b"1.947  \r\x06"),
        (2, 1, Answer(("1", "7.6")), b"1\r7.6\r\x06"),
        (2, 1, Answer(), b"\x06"),
        (2, 1, Answer(error="ERR003"), b"\x07ERR003\r"),
        (2, 1, Answer(("12",), "ERR005"), b"12\r\x07ERR005\r"),
        (0, 1, Answer(("5",)), b"5\r"),
        (0, 0, Answer(error="ERR003"), b"\x07"),
        (1, 1, Answer(("5", "6")), b"\n5\r\n6\r\n"),
        (1, 3, Answer(error="ERR004"), b"\n\x07\rERR004\r"),
        (3, 1, Answer(("5",)), b"\n5\r\x06"),
        (2, 2, Answer(error="ERR001"), b"\x07"),
        (6, 5, Answer(("5",)), b"5\r\x06"),  # I3=6 wraps to 2, I6=5 to 1
    ],
)
def test_reply_framing_follows_i3_and_i6(i3: int, i6: int, answer: Answer, wire: bytes) -> None:
    """Spec §2.1 (I3 table) and §2.2 (I6 error formats)."""
    assert frame(answer, i3, i6) == wire


def test_non_err_error_text_is_reported_as_err003() -> None:
    assert Answer.from_reply("", "something broke").error == "ERR003"
    assert Answer.from_reply("1\r2", None).lines == ("1", "2")


def test_getresponse_returns_first_response_and_queues_the_rest_for_getbuffer() -> None:
    """GETRESPONSE returns up to the ACK, at most 1400 bytes; the rest is fetched by GETBUFFER
    (the loop dls-pmaclib runs for long replies)."""
    codec = PmacEthernetCodec()
    (req,) = feed(codec, getresponse("I100..299"))
    lines = tuple(str(n) for n in range(1000, 1200))  # 200 lines of 5 bytes = 1001 bytes
    big = Answer(lines + lines)  # 2001 bytes
    first = codec.reply(req, [big])
    # byte 1400 is a CR (5-byte lines): the piece takes one byte more, never ending in CR
    assert len(first) == MAX_REPLY + 1 and not first.endswith((b"\x06", b"\r"))
    assert codec.reply(ReadReady()) == b"\x01\x00"
    rest = codec.reply(GetBuffer(2048))
    assert first + rest == frame(big)
    assert codec.reply(ReadReady()) == b"\x00\x00"
    assert codec.reply(GetBuffer(2048)) == EMPTY


def test_several_lines_in_one_getresponse_queue_one_response_each() -> None:
    codec = PmacEthernetCodec()
    (req,) = feed(codec, getresponse("I5\rI6\r"))
    assert req == GetResponse(("I5", "I6"))
    assert codec.reply(req, [Answer(("1",)), Answer(("1",))]) == b"1\r\x06"
    assert codec.reply(GetBuffer(0)) == b"1\r\x06"


def test_flush_answers_at_sign_and_discards_queued_output() -> None:
    """EPICS: VR_PMAC_FLUSH then read 1 byte; hardware answers 0x40 '@'."""
    codec = PmacEthernetCodec()
    codec.queue(b"stale\r\x06")
    (req,) = feed(codec, bytes.fromhex("40b3000000000000"))
    assert codec.reply(req) == b"@"
    assert codec.reply(ReadReady()) == b"\x00\x00"


def test_getline_returns_queued_text_up_to_cr() -> None:
    codec = PmacEthernetCodec()
    codec.queue(b"1\r2\r\x06")
    assert [codec.reply(GetLine()) for _ in range(4)] == [b"1\r", b"2\r", b"\x06", EMPTY]


def test_sendline_answers_one_byte_and_queues_the_output() -> None:
    codec = PmacEthernetCodec()
    (req,) = feed(codec, pack_request(VR_DOWNLOAD, VR.PMAC_SENDLINE, payload=b"PR"))
    assert req == SendLine(("PR",))
    assert codec.reply(req, [Answer(("7",))]) == ACK_BYTE
    assert codec.reply(GetLine()) == b"7\r"


def test_ctrl_response_takes_the_character_from_either_byte_of_wvalue() -> None:
    """C clients htons() wValue; the EPICS driver puts the character in host order."""
    codec = PmacEthernetCodec()
    got = feed(codec, bytes.fromhex("c0c4001000000000") + bytes.fromhex("c0c4100000000000"))
    assert got == [CtrlResponse(0x10), CtrlResponse(0x10)]
    assert codec.reply(got[0], [Answer(("0 0",))]) == b"0 0\r\x06"


def test_writebuffer_splits_nul_terminated_lines_and_reports_failing_line() -> None:
    """4-byte answer: byte3 0x80 on error, byte2 the error number, bytes 1:0 the line."""
    codec = PmacEthernetCodec()
    payload = b"OPEN ROT\x00X1\x00X2\x00CLOSE\x00"
    (req,) = feed(codec, pack_request(VR_DOWNLOAD, VR.PMAC_WRITEBUFFER, payload=payload))
    assert req == WriteBuffer(("OPEN ROT", "X1", "X2", "CLOSE"))
    assert codec.reply(req, [Answer()] * 4) == b"\x00\x00\x00\x00"
    assert codec.reply(req, [Answer(), Answer(error="ERR006")]) == b"\x01\x00\x06\x80"
    assert write_buffer_status("ERR005", 0x0102) == b"\x02\x01\x05\x80"


def test_port_write_builds_a_line_until_cr_and_port_read_returns_bytes() -> None:
    codec = PmacEthernetCodec()
    reqs = feed(codec, b"".join(
        pack_request(VR_DOWNLOAD, VR.PMAC_PORT, value=ord(c)) for c in "PR\r"
    ))
    assert reqs == [PortWrite(ord("P")), PortWrite(ord("R")), PortWrite(13)]
    assert [codec.port_write(r.char) for r in reqs] == [None, None, "PR"]
    # a C client's htons(wValue) puts the character in the high byte: taken from there too
    swapped = feed(codec, b"".join(
        pack_request(VR_DOWNLOAD, VR.PMAC_PORT, value=ord(c) << 8) for c in "PR\r"))
    assert swapped == [PortWrite(ord("P")), PortWrite(ord("R")), PortWrite(13)]
    codec.queue(b"7\r\x06")
    assert feed(codec, pack_request(VR_UPLOAD, VR.PMAC_PORT)) == [PortRead()]
    assert [codec.reply(PortRead()) for _ in range(4)] == [b"7", b"\r", b"\x06", EMPTY]


def test_dpram_requests_are_acknowledged_without_effect() -> None:
    codec = PmacEthernetCodec()
    reqs = feed(codec, pack_request(VR_DOWNLOAD, VR.PMAC_SETMEM, payload=b"\x01\x02")
                + pack_request(VR_UPLOAD, VR.PMAC_GETMEM, value=16, length=4)
                + pack_request(VR_UPLOAD, VR.IPADDRESS, length=4))
    assert [type(r) for r in reqs] == [Memory, Memory, Memory]
    assert [codec.reply(r) for r in reqs] == [ACK_BYTE, b"\x00" * 4, b"\x7f\x00\x00\x01"]


# -- bad input -------------------------------------------------------------------------


def test_short_header_needs_data_and_nothing_is_decoded() -> None:
    codec = PmacEthernetCodec()
    assert feed(codec, b"\x40\xbf\x00") == []
    codec.receive_data(b"")
    assert codec.eof and codec.pending_bytes == 3


def test_wlength_beyond_the_data_sent_waits_and_never_executes_part_of_it() -> None:
    codec = PmacEthernetCodec()
    packet = pack_request(VR_DOWNLOAD, VR.PMAC_WRITEBUFFER, payload=b"X1\x00X2\x00X3\x00")
    assert feed(codec, packet[:-4]) == []
    codec.receive_data(b"")  # the host disconnects mid-request
    assert codec.next_request() is NEED_DATA


@pytest.mark.parametrize(
    "header",
    [
        bytes.fromhex("00bf000000000000"),  # RequestType neither 0x40 nor 0xC0
        bytes.fromhex("40aa000000000000"),  # unknown Request code
        bytes.fromhex("c0bf000000000004"),  # GETRESPONSE sent as an upload
        pack_request(VR_DOWNLOAD, VR.PMAC_GETRESPONSE, length=1493),  # oversized payload
    ],
)
def test_a_broken_stream_is_a_protocol_error_and_stays_broken(header: bytes) -> None:
    codec = PmacEthernetCodec()
    codec.receive_data(header + b"\x00" * 16)
    with pytest.raises(ProtocolError):
        codec.next_request()
    with pytest.raises(ProtocolError):
        codec.next_request()


def test_bytes_above_127_are_found_for_err004() -> None:
    assert illegal_character("I5") is None
    assert illegal_character("I\xe95") == 1
    codec = PmacEthernetCodec()
    (req,) = feed(codec, getresponse(b"I\xe95"))
    assert illegal_character(req.lines[0]) == 1


def test_a_piece_never_ends_in_cr_while_the_response_goes_on() -> None:
    """700 lines of ``0\\r`` put a CR at byte 1400: the piece carries the ACK over, so a client
    reading "ends in CR" as a finished (error) reply is not left one reply behind."""
    codec = PmacEthernetCodec()
    (req,) = feed(codec, getresponse("P0..699"))
    first = codec.reply(req, [Answer(("0",) * 700)])
    assert first == b"0\r" * 700 + b"\x06"
    assert codec.reply(ReadReady()) == b"\x00\x00"
