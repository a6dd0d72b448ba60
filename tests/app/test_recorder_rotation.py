"""``--record FILE`` never overwrites the last run's transcript: the old one is rotated."""

from __future__ import annotations

from motionsim.app.recorder import KEEP, Recorder, read_transcript


def _run(path, peer: str) -> None:
    rec = Recorder(path, {"pmac": {"kind": "pmac", "config": {}}})
    session = rec.open_session("pmac", "pmac", 0.0, peer)
    rec.record(session, "in", b"I16", 0.0)
    rec.close_session(session, 0.1)
    rec.close()


def _peer(path) -> str:
    return next(r for r in read_transcript(path) if r.kind == "open").fields["peer"]


def test_a_second_run_keeps_the_first_runs_transcript(tmp_path):
    path = tmp_path / "wire.jsonl"
    _run(path, "first")
    _run(path, "second")
    assert _peer(path) == "second"
    assert _peer(tmp_path / "wire.jsonl.1") == "first"


def test_only_the_newest_transcripts_are_kept(tmp_path):
    path = tmp_path / "wire.jsonl"
    for n in range(KEEP + 3):
        _run(path, f"run{n}")
    assert _peer(path) == f"run{KEEP + 2}"
    assert [_peer(tmp_path / f"wire.jsonl.{k}") for k in range(1, KEEP + 1)] == [
        f"run{KEEP + 2 - k}" for k in range(1, KEEP + 1)]
    assert not (tmp_path / f"wire.jsonl.{KEEP + 1}").exists()
