"""The commands of ``examples/trio/README.md`` work as written, from the repository root,
against a served motionsim (the README's curl session, with the fixture's URL)."""

from __future__ import annotations

import json
import re
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _shell_block(readme: Path) -> str:
    text = readme.read_text()
    return re.search(r"```sh\n(.*?)```", text, re.S).group(1)


def _json_documents(text: str) -> list:
    """The JSON documents curl printed one after the other (no separator between them)."""
    decoder, docs, i = json.JSONDecoder(), [], 0
    while i < len(text):
        if text[i].isspace():
            i += 1
            continue
        doc, i = decoder.raw_decode(text, i)
        docs.append(doc)
    return docs


def test_trio_readme_session_runs_from_the_repo_root_and_shows_the_tn20_stall(motionsim):
    script = _shell_block(ROOT / "examples" / "trio" / "README.md")
    assert "http://127.0.0.1:8000" in script
    script = script.replace("http://127.0.0.1:8000", motionsim.url)
    out = subprocess.run(["bash", "-euo", "pipefail", "-c", script], cwd=ROOT,
                         capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    events = _json_documents(out.stdout)[-1]["events"]  # the last curl: the events page
    assert motionsim.controller("t")["clock"]["t"] == pytest.approx(0.3)
    blocked = [e for e in events if e["type"] == "process" and e["state"] == "blocked"]
    assert blocked, "the TN20 program never waited at a move line"
    # the VR table written in one request is what the program moved by
    assert motionsim.http.get("/controllers/t/variables/VR%28150%29").json()["value"] == 200
