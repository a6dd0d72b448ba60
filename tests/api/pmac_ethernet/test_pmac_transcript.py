"""``--record FILE`` transcripts and ``motionsim replay FILE``: a recorded PMAC session replays
byte for byte against a fresh controller; a changed answer is reported with its offset."""

from __future__ import annotations

import asyncio
import json
from pathlib import Path

from motionsim.api.pmac_ethernet.protocol import VR, VR_DOWNLOAD, getresponse, pack_request
from motionsim.api.pmac_ethernet.server import serve_pmac
from motionsim.app.recorder import read_transcript
from motionsim.app.replay import main as replay_main
from motionsim.app.replay import replay

from tests.api.wire_helpers import connect, serving


def record_session(path: Path) -> None:
    async def scenario():
        async with serving(serve_pmac, "wirepmac", "pmac", record_to=path) as (handle, port):
            reader, writer = await connect(port)
            for cmd in ("i6=1 i3=2 ver", "cid", "OPEN ROT", "X1", "BOGUS"):
                writer.write(getresponse(cmd))
                await writer.drain()
                await asyncio.wait_for(reader.read(4096), 2)
            writer.write(pack_request(VR_DOWNLOAD, VR.PMAC_FLUSH))
            await asyncio.wait_for(reader.readexactly(1), 2)
            handle.clock.advance(0.25)
            writer.write(getresponse("I16 I17"))
            await asyncio.wait_for(reader.read(4096), 2)
            writer.close()
            await writer.wait_closed()
            await asyncio.sleep(0.05)

    asyncio.run(scenario())


def test_transcript_holds_bytes_with_simulated_and_wall_times(tmp_path: Path) -> None:
    path = tmp_path / "wire.jsonl"
    record_session(path)
    records = list(read_transcript(path))
    assert [r.kind for r in records[:3]] == ["header", "open", "in"]
    assert records[0].fields["controllers"] == {"pmac": {"kind": "wirepmac", "config": {}}}
    ins = [r for r in records if r.kind == "in"]
    outs = [r for r in records if r.kind == "out"]
    assert ins[0].data == getresponse("i6=1 i3=2 ver")
    assert outs[0].data == b"1.947  \r\x06" and outs[4].data == b"\x07ERR003\r"
    assert outs[0].t == 0.0005 and ins[-1].t == 0.25 + 0.0005 * 5
    assert all(r.wall > 1.6e9 for r in records[1:])
    assert records[-1].kind == "close"


def test_replay_matches_a_recorded_session_byte_for_byte(tmp_path: Path, capsys) -> None:
    path = tmp_path / "wire.jsonl"
    record_session(path)
    result = asyncio.run(replay(path))
    assert result.ok and len(result.sessions) == 1
    assert result.sessions[0].got.startswith(b"1.947  \r\x06603382\r\x06")
    assert replay_main(path) == 0
    assert "1/1 sessions match" in capsys.readouterr().out


def test_replay_reports_the_first_differing_byte(tmp_path: Path) -> None:
    path = tmp_path / "wire.jsonl"
    record_session(path)
    lines = path.read_text().splitlines()
    for i, line in enumerate(lines):
        obj = json.loads(line)
        if obj.get("data") == "603382\r\u0006":
            obj["data"] = "602413\r\u0006"
            lines[i] = json.dumps(obj)
            break
    path.write_text("\n".join(lines) + "\n")
    result = asyncio.run(replay(path))
    assert not result.ok
    assert result.sessions[0].first_difference == len(b"1.947  \r\x06") + 2
    assert replay_main(path) == 1
