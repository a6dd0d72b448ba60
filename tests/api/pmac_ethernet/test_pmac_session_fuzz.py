"""Fuzz the whole PMAC path — codec, session, the real ``pmac`` kind — with generated requests:
each answer is bytes the client can frame, or the stream is a ProtocolError; nothing else
escapes, nothing hangs."""

from __future__ import annotations

import asyncio

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from motionsim.api.pmac_ethernet.protocol import (
    VR,
    VR_DOWNLOAD,
    VR_UPLOAD,
    ProtocolError,
    pack_request,
)
from motionsim.api.pmac_ethernet.server import PmacSession
from motionsim.app.registry import Registry

WORDS = ["I16", "I17=3", "P1=2", "&1", "&2", "#1", "DEFINE ROT 50", "OPEN ROT", "CLOSE", "X1",
         "Y2.5", "B0", "R", "Q", "A", "PR", "??", "?", "???", "M1==1", "DWELL 10", "TM 5",
         "DELETE ROT", "DELETE GATHER", "I100", "F10", "LINEAR", "I3=1", "I3=2", "I6=3",
         "ver", "cid", "P1=1/0", "P(5)=3", "#1->X", "I5..7", "(", "=", "\x02", "\xff"]

command = st.lists(st.sampled_from(WORDS), min_size=0, max_size=4).map(" ".join)
request = st.one_of(
    command.map(lambda c: pack_request(VR_DOWNLOAD, VR.PMAC_GETRESPONSE,
                                       payload=c.encode("latin-1"))),
    st.lists(command, max_size=4).map(lambda cs: pack_request(
        VR_DOWNLOAD, VR.PMAC_WRITEBUFFER, payload=b"".join(c.encode("latin-1") + b"\0"
                                                           for c in cs))),
    st.sampled_from([pack_request(VR_UPLOAD, VR.PMAC_GETBUFFER, length=2048),
                     pack_request(VR_UPLOAD, VR.PMAC_READREADY, length=2),
                     pack_request(VR_DOWNLOAD, VR.PMAC_FLUSH),
                     pack_request(VR_UPLOAD, VR.CTRL_RESPONSE, value=0x10)]),
    st.binary(min_size=1, max_size=12),
)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(request, min_size=1, max_size=8))
def test_any_requests_through_the_real_pmac_kind(requests: list[bytes]) -> None:
    async def main() -> None:
        registry = Registry()
        handle = registry.add("pmac", "pmac", clock="virtual")
        session = PmacSession(handle, "fuzz")
        try:
            for packet in requests:
                session.receive(packet)

                async def drain() -> None:
                    async for out in session.replies():
                        assert isinstance(out, bytes) and out

                try:
                    await asyncio.wait_for(drain(), 5)
                except ProtocolError:
                    return
        finally:
            session.close()
            await registry.close()

    asyncio.run(main())
