"""A recorded Trio session — including a command line locked on a move — replays byte for byte
(``motionsim replay FILE``), with the lock released at the same simulated instant."""

from __future__ import annotations

import asyncio
from pathlib import Path

from motionsim.api.trio_terminal.server import serve_trio
from motionsim.app.cli import cli
from motionsim.app.recorder import read_transcript
from motionsim.app.replay import replay
from typer.testing import CliRunner

from tests.api.wire_helpers import connect, serving


def record_locked_session(path: Path) -> bytes:
    async def scenario() -> bytes:
        async with serving(serve_trio, "wiretrio", "trio", record_to=path) as (handle, port):
            reader, writer = await connect(port)
            writer.write(b"?1\r\nMOVE(1)\r\n?VR(2)\r\n")
            seen = await asyncio.wait_for(reader.readuntil(b"MOVE(1)\r\n"), 2)
            await asyncio.sleep(0.05)
            handle.clock.advance(0.02)
            seen += await asyncio.wait_for(reader.readuntil(b"0.0000\r\n>>"), 2)
            writer.close()
            await writer.wait_closed()
            await asyncio.sleep(0.05)
        return seen

    return asyncio.run(scenario())


def test_locked_session_replays_identically(tmp_path: Path) -> None:
    path = tmp_path / "trio.jsonl"
    seen = record_locked_session(path)
    assert seen == b"?1\r\n1.0000\r\n>>MOVE(1)\r\n>>?VR(2)\r\n0.0000\r\n>>"
    outs = [r for r in read_transcript(path) if r.kind == "out"]
    # sent once the clock, advanced to 0.02 s, had buffered the move (at 0.01 s)
    assert [(r.t, r.data) for r in outs if r.data == b">>"] == [(0.02, b">>")]
    result = asyncio.run(replay(path))
    assert result.ok, [s.describe() for s in result.sessions]
    assert result.sessions[0].got == seen


def test_motionsim_replay_command_exit_status(tmp_path: Path) -> None:
    path = tmp_path / "trio.jsonl"
    record_locked_session(path)
    ok = CliRunner().invoke(cli, ["replay", str(path)])
    assert ok.exit_code == 0 and "1/1 sessions match" in ok.output
    path.write_text(path.read_text().replace("1.0000", "9.0000"))
    bad = CliRunner().invoke(cli, ["replay", str(path)])
    assert bad.exit_code == 1 and "differs at byte 4" in bad.output
