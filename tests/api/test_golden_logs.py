"""Golden event logs of a PMAC and a Trio session through the whole service stack (REST in
process, virtual clocks): the log of each is compared byte for byte with the copy stored in
``tests/api/golden/``, and must be the same on every run and under every hash seed.

A change that is *meant* to change simulated behaviour (a timing rule, a new event) updates the
copies with ``MOTIONSIM_UPDATE_GOLDEN=1 pytest tests/api/test_golden_logs.py``; the commit then
says why the log changed. A change that is not meant to (a refactor, a speed-up) must leave them
as they are.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import httpx
import pytest
from motionsim.api.main import create_app

from tests.conftest import dummy_settings, rest_client

pytestmark = pytest.mark.anyio

GOLDEN = Path(__file__).parent / "golden"

TN20 = (Path(__file__).resolve().parents[2] / "examples" / "trio" / "tn20_blocking.bas").read_text()


async def _log(c: httpx.AsyncClient, cid: str) -> str:
    events, since = [], 0
    while True:
        page = (await c.get(f"/controllers/{cid}/events",
                            params={"since": since, "limit": 500})).json()
        events += page["events"]
        if page["next"] == since:
            break
        since = page["next"]
    return "".join(json.dumps(e, separators=(",", ":"), sort_keys=True) + "\n" for e in events)


async def _pmac_session(c: httpx.AsyncClient) -> None:
    """I16/I17 set on-line, a rotary stream with a synchronous M write and a DWELL, PLC 0
    counting, PR polls between advances, then Q, more lines, R and A."""
    base = "/controllers/p"

    async def term(command: str) -> None:
        r = await c.post(f"{base}/terminal", json={"command": command})
        assert r.status_code == 200, r.text

    async def advance(seconds: float) -> None:
        assert (await c.post(f"{base}/clock/advance", json={"seconds": seconds})).status_code == 200

    await term("I16=3 I17=6")
    await term("&1 #1->X #2->Y")
    await term("&1 DEFINE ROT 200")
    await c.put(f"{base}/plcs/0", json={"text": "P1=P1+1\nIF (P1>100)\n  P2=1\nENDIF"})
    await c.post(f"{base}/plcs/0/enable")
    lines = ["INC LINEAR TA5 TS0 TM10", "X1 Y1", "M1==1", "X2", "DWELL 5", "X1 Y-1"]
    lines += [f"X{i % 3} Y{(i * 7) % 5}" for i in range(20)]
    r = await c.post(f"{base}/coord/1/rotary/lines", json={"lines": lines[:8], "first_seq": 1})
    assert r.status_code == 200, r.text
    await c.post(f"{base}/coord/1/run")
    sent = 8
    for _ in range(12):
        await advance(0.013)
        await term("PR")
        if sent < len(lines):
            r = await c.post(f"{base}/coord/1/rotary/lines",
                             json={"lines": lines[sent:sent + 3], "first_seq": sent + 1})
            assert r.status_code == 200, r.text
            sent += 3
    await term("&1 Q")
    await advance(0.1)
    await term("&1 R")
    await advance(0.02)
    await term("&1 A")
    await advance(0.05)


async def _trio_session(c: httpx.AsyncClient) -> None:
    """TN20-16's blocking program (short moves on axis 0, long ones on axis 1), a move from
    REST on axis 2, and a command-line query while the program runs."""
    base = "/controllers/t"
    for n in range(1, 51):
        await c.put(f"{base}/variables/VR({n})", json={"value": 10})
        await c.put(f"{base}/variables/VR({100 + n})", json={"value": 200})
    assert (await c.put(f"{base}/programs/TN20", content=TN20,
                        headers={"content-type": "text/plain"})).status_code in (200, 201)
    await c.post(f"{base}/programs/TN20/run", json={"process": 1})
    await c.post(f"{base}/axes/2/moves", json={"type": "MOVE", "args": [50]})
    for _ in range(6):
        await c.post(f"{base}/clock/advance", json={"seconds": 0.05})
        await c.post(f"{base}/terminal", json={"command": "PRINT MTYPE AXIS(0)"})


SESSIONS = {
    "pmac": ("p", {"id": "p", "kind": "pmac", "clock": {"mode": "virtual"}}, _pmac_session),
    "trio": ("t", {"id": "t", "kind": "trio", "clock": {"mode": "virtual"},
                   "config": {"speed": 1000, "accel": 100000, "decel": 100000}}, _trio_session),
}


async def _run(kind: str) -> str:
    cid, controller, session = SESSIONS[kind]
    async with rest_client(create_app(dummy_settings(controllers=[controller]))) as c:
        await session(c)
        return await _log(c, cid)


@pytest.mark.parametrize("kind", sorted(SESSIONS))
async def test_the_session_log_matches_the_golden_copy_byte_for_byte(kind):
    got = await _run(kind)
    assert got == await _run(kind)  # the same inputs twice: the same bytes
    path = GOLDEN / f"{kind}_session.jsonl"
    if os.environ.get("MOTIONSIM_UPDATE_GOLDEN") == "1":
        path.write_text(got)
    want = path.read_text()
    assert got == want, (f"{kind} log differs from {path.name}; if the behaviour change is "
                         "intended, regenerate with MOTIONSIM_UPDATE_GOLDEN=1 and say why")


def test_the_golden_logs_cover_the_behaviour_they_stand_for():
    """The stored copies are not trivially small: they hold the events the sessions exist for."""
    types = {k: {json.loads(x)["type"] for x in (GOLDEN / f"{k}_session.jsonl").read_text()
                 .splitlines()} for k in SESSIONS}
    assert {"breq", "line_loaded", "line_calculated", "move_start", "move_end", "mvar",
            "program", "plc"} <= types["pmac"]
    assert {"axis", "process_buffer", "process", "move_start", "move_end"} <= types["trio"]
