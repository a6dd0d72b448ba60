"""Fuzz: any byte stream decodes to requests, waits for data, or is a ProtocolError — and every
request decoded gets an answer. At least 10 000 generated frames (1 000 examples × ≥ 10)."""

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from motionsim.api.pmac_ethernet.protocol import (
    EXECUTES,
    MAX_PAYLOAD,
    MAX_PIECE,
    NEED_DATA,
    VR,
    Answer,
    PmacEthernetCodec,
    PortWrite,
    ProtocolError,
    pack_request,
)

answers = st.builds(
    Answer,
    st.lists(st.text(max_size=30), max_size=5).map(tuple),
    st.one_of(st.none(), st.sampled_from(["ERR003", "ERR004", "ERR006", "oops"])),
)

frame_st = st.builds(
    lambda rtype, code, value, index, payload, length: pack_request(
        rtype, code, value, index, payload, length
    ),
    st.one_of(st.sampled_from([0x40, 0xC0]), st.integers(0, 255)),
    st.one_of(st.sampled_from([int(v) for v in VR]), st.integers(0, 255)),
    st.integers(0, 0xFFFF),
    st.integers(0, 0xFFFF),
    st.binary(max_size=64),
    st.one_of(st.none(), st.integers(0, 0xFFFF)),
)


@settings(max_examples=1000, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    frames=st.lists(frame_st, min_size=10, max_size=14),
    cuts=st.lists(st.integers(1, 40), max_size=8),
    replies=st.lists(answers, min_size=1, max_size=3),
    i3=st.integers(0, 7),
    i6=st.integers(0, 7),
)
def test_any_stream_decodes_or_is_a_protocol_error(frames, cuts, replies, i3, i6) -> None:
    stream = b"".join(frames)
    codec = PmacEthernetCodec()
    pos = 0
    for cut in [*cuts, len(stream)]:
        codec.receive_data(stream[pos : pos + cut] if cut < len(stream) else stream[pos:])
        pos = min(len(stream), pos + cut)
        try:
            while (req := codec.next_request()) is not NEED_DATA:
                if isinstance(req, PortWrite):
                    codec.port_write(req.char)
                out = codec.reply(req, replies if isinstance(req, EXECUTES) else (), i3=i3, i6=i6)
                assert isinstance(out, bytes) and 1 <= len(out) <= MAX_PIECE
        except ProtocolError:
            return
        if pos >= len(stream):
            break
    assert codec.pending_bytes <= len(stream)
    assert codec.pending_bytes < 8 + MAX_PAYLOAD
