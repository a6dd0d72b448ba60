"""The Trio command-line codec without sockets: line ends, echo, prompt, telnet negotiation.

Facts: spec trio.md §0.10–0.11, §3.1, §9.9 (prompt ``>>``, reply on the next line then ``>>``).
"""

from hypothesis import given, settings
from hypothesis import strategies as st
from motionsim.api.trio_terminal.protocol import (
    DO,
    DONT,
    IAC,
    MAX_LINE,
    NEED_DATA,
    SB,
    SE,
    WILL,
    WONT,
    Line,
    TrioTerminalCodec,
)


def lines(codec: TrioTerminalCodec, data: bytes) -> list[str]:
    codec.receive_data(data)
    out = []
    while (line := codec.next_line()) is not NEED_DATA:
        out.append(line.text)
    return out


def test_print_free_reply_then_prompt() -> None:
    """``>>PRINT FREE`` / ``47104.0000`` / ``>>`` (M224-291)."""
    codec = TrioTerminalCodec()
    assert lines(codec, b"PRINT FREE\r\n") == ["PRINT FREE"]
    assert codec.data_to_send() == b"PRINT FREE\r\n"
    assert codec.reply("47104.0000") == b"47104.0000\r\n>>"


def test_line_ends_cr_lf_crlf_and_cr_nul_are_one_line_each() -> None:
    codec = TrioTerminalCodec(echo=False)
    assert lines(codec, b"A\rB\nC\r\nD\r\x00E") == ["A", "B", "C", "D"]
    assert lines(codec, b"\r") == ["E"]
    assert codec.data_to_send() == b""


def test_empty_line_is_an_empty_command() -> None:
    codec = TrioTerminalCodec()
    assert lines(codec, b"\r\n") == [""]
    assert codec.reply() == b">>"


def test_backspace_and_escape_edit_the_line() -> None:
    codec = TrioTerminalCodec()
    assert lines(codec, b"VX(1\x08\x08\x08R(2)\r") == ["VR(2)"]
    assert lines(codec, b"MOVE(1\x1b?1\r") == ["?1"]


def test_lines_after_a_pending_one_are_neither_read_nor_echoed() -> None:
    """While a command is pending the server stops asking for lines: nothing more is echoed."""
    codec = TrioTerminalCodec()
    codec.receive_data(b"MOVE(10)\r?1\r")
    assert codec.next_line() == Line("MOVE(10)")
    assert codec.data_to_send() == b"MOVE(10)\r\n"
    assert codec.data_to_send() == b""
    assert codec.next_line() == Line("?1")
    assert codec.data_to_send() == b"?1\r\n"


def test_error_and_multi_line_replies_end_crlf_and_prompt() -> None:
    out = TrioTerminalCodec.reply("1.0000\n2.0000\n", "%Command not recognised")
    assert out == b"1.0000\r\n2.0000\r\n%Command not recognised\r\n>>"


def test_telnet_negotiation_is_answered_and_never_reaches_the_line() -> None:
    codec = TrioTerminalCodec()
    data = bytes([IAC, DO, 1, IAC, DO, 24, IAC, WILL, 31, IAC, WONT, 5,
                  IAC, SB, 24, 0, 65, 66, IAC, SE]) + b"?1\r\n"
    assert lines(codec, data) == ["?1"]
    assert codec.data_to_send() == bytes([IAC, WILL, 1, IAC, WONT, 24, IAC, DONT, 31]) + b"?1\r\n"


def test_overlong_line_is_cut() -> None:
    codec = TrioTerminalCodec(echo=False)
    assert lines(codec, b"X" * (MAX_LINE + 50) + b"\r") == ["X" * MAX_LINE]


@settings(max_examples=300, deadline=None)
@given(st.lists(st.binary(max_size=40), max_size=10))
def test_any_bytes_give_lines_or_need_data(chunks: list[bytes]) -> None:
    codec = TrioTerminalCodec()
    for chunk in chunks:
        for text in lines(codec, chunk):
            assert "\r" not in text and "\n" not in text and len(text) <= MAX_LINE
        codec.data_to_send()
