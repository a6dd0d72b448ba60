"""``motionsim replay`` of a corrupt transcript and ``--record`` on a path that is not one
(issue 33 item 7): one line naming the file and line, exit status 2, no traceback; nothing of
a directory or of another file is renamed."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from motionsim.app.cli import cli
from motionsim.app.recorder import Recorder, check_path, read_transcript
from motionsim.app.replay import main as replay_main
from typer.testing import CliRunner

HEADER = json.dumps({"kind": "header", "version": 1,
                     "controllers": {"pmac": {"kind": "pmac", "config": {}}}})
OPEN = json.dumps({"kind": "open", "session": 1, "protocol": "pmac", "controller": "pmac",
                   "t": 0.0})


@pytest.mark.parametrize(("bad", "says"), [
    ("not json at all", "not JSON"),
    ('{"kind": "in", "session": 1, "t": 0.1, "data": 5}', "field 'data' is int"),
    ('{"kind": "in", "session": "one", "t": 0.1, "data": "x"}', "field 'session' is str"),
    ('{"kind": "open", "session": 2}', "needs 'protocol'"),
    ('{"kind": "in", "session": 7, "t": 0.1, "data": "x"}', "unknown session 7"),
    ('{"kind": "open", "session": 2, "protocol": "pmac", "controller": "nope"}', "'nope'"),
    ('[1, 2]', "JSON object"),
    ('{"kind": "teleport"}', "unknown record kind"),
])
def test_a_corrupt_line_is_one_message_with_its_line_number(tmp_path, capsys, bad, says):
    path = tmp_path / "t.jsonl"
    path.write_text(f"{HEADER}\n{OPEN}\n{bad}\n", encoding="utf-8")
    assert replay_main(path) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "Traceback" not in err
    assert f"{path}:3:" in err and says in err


def test_a_good_transcript_still_reads(tmp_path):
    path = tmp_path / "t.jsonl"
    path.write_text(f"{HEADER}\n{OPEN}\n", encoding="utf-8")
    assert [r.kind for r in read_transcript(path)] == ["header", "open"]
    assert [r.line for r in read_transcript(path)] == [1, 2]


def test_record_refuses_a_directory_and_a_file_that_is_not_a_transcript(tmp_path):
    folder = tmp_path / "logs"
    folder.mkdir()
    notes = tmp_path / "notes.txt"
    notes.write_text("my notes\n", encoding="utf-8")
    for path, says in ((folder, "is a directory"), (notes, "is not a motionsim transcript")):
        with pytest.raises(ValueError, match=says):
            Recorder(path)
    assert folder.is_dir() and notes.read_text(encoding="utf-8") == "my notes\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["logs", "notes.txt"]


def test_record_still_keeps_an_older_transcript(tmp_path):
    path = tmp_path / "t.jsonl"
    Recorder(path).close()
    check_path(path)  # a transcript: fine to rotate
    Recorder(path).close()
    assert (tmp_path / "t.jsonl.1").exists()


def test_serve_record_on_a_directory_exits_2_with_one_line(tmp_path: Path):
    folder = tmp_path / "logs"
    folder.mkdir()
    result = CliRunner().invoke(cli, ["serve", "--port", "0", "--record", str(folder)])
    assert result.exit_code == 2
    assert "--record" in result.output and "is a directory" in result.output
    assert folder.is_dir() and not (tmp_path / "logs.1").exists()
