"""Control characters over the PMAC Ethernet protocol, on the real ``pmac`` kind.

dls-pmac-control's "kill all" sends CTRL-K ($0B) as the text of a VR_PMAC_GETRESPONSE
(``sendCommand("\\x0b")``); the EPICS driver asks reports with VR_CTRL_RESPONSE (spec pmac.md
§5.3, §11.9). $0B used to be dropped as white space.
"""

from __future__ import annotations

from motionsim.api.pmac_ethernet.protocol import VR, VR_UPLOAD, pack_request

from tests.api.pmac_ethernet.test_pmac_server import Client, run


def test_ctrl_k_in_a_getresponse_kills_all_motors() -> None:
    async def scenario(handle, port):
        c = await Client.connect(port)
        got = [await c.ask("i3=2"), await c.ask("\x0b"), await c.ask("#1?")]
        await c.close()
        return got

    ack, kill, status = run(scenario, kind="pmac")
    assert (ack, kill) == (b"\x06", b"\x06")
    w1 = int(status[:6], 16)
    assert status.endswith(b"\r\x06") and not w1 & (1 << 19) and w1 & (1 << 18)


def test_ctrl_b_by_vr_ctrl_response_reports_eight_status_words() -> None:
    async def scenario(handle, port):
        c = await Client.connect(port)
        await c.ask("i3=2")
        reply = await c.send(pack_request(VR_UPLOAD, VR.CTRL_RESPONSE, value=0x02, length=1400))
        again = await c.ask("#1?")
        await c.close()
        return reply, again

    reply, again = run(scenario, kind="pmac")
    words = reply.rstrip(b"\r\x06").split(b" ")
    assert len(words) == 8 and words[0] == again.rstrip(b"\r\x06")


def test_an_unknown_control_character_answers_err003_and_the_connection_goes_on() -> None:
    async def scenario(handle, port):
        c = await Client.connect(port)
        await c.ask("i3=2")
        got = [await c.ask("\x1a"), await c.ask("cid")]
        await c.close()
        return got

    assert run(scenario, kind="pmac") == [b"\x07ERR003\r", b"603382\r\x06"]
