"""The commands of ``examples/trio/README.md`` and ``examples/pmac/README.md`` work as
written, from the folder they say, against a served motionsim (the README's curl sessions,
with the fixture's URL)."""

from __future__ import annotations

import json
import re
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _shell_block(readme: Path, k: int = 0) -> str:
    text = readme.read_text()
    return re.findall(r"```sh\n(.*?)```", text, re.S)[k]


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


def test_trio_readme_session_runs_from_a_copy_of_the_examples_and_shows_the_tn20_stall(
        motionsim, tmp_path):
    """Run where a user runs it: the README's own folder in the copy ``motionsim examples``
    writes (issue 36 item 5: it spoke of the repository root)."""
    from motionsim.app.cli import cli
    from typer.testing import CliRunner

    assert CliRunner().invoke(cli, ["examples", str(tmp_path / "ex")]).exit_code == 0
    script = _shell_block(tmp_path / "ex" / "trio" / "README.md")
    assert "http://127.0.0.1:8000" in script
    script = script.replace("http://127.0.0.1:8000", motionsim.url)
    out = subprocess.run(["bash", "-euo", "pipefail", "-c", script], cwd=tmp_path / "ex" / "trio",
                         capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    events = _json_documents(out.stdout)[-1]["events"]  # the last curl: the events page
    assert motionsim.controller("t")["clock"]["t"] == pytest.approx(0.3)
    blocked = [e for e in events if e["type"] == "process" and e["state"] == "blocked"]
    assert blocked, "the TN20 program never waited at a move line"
    # the VR table written in one request is what the program moved by
    assert motionsim.http.get("/controllers/t/variables/VR%28150%29").json()["value"] == 200


def test_pmac_readme_session_runs_after_make_run_on_a_virtual_controller_of_its_own(
        pmac_and_trio_realtime):
    """``make run`` serves ``pmac`` and ``trio`` on a realtime clock: the README's session
    makes its own virtual-clock controller, so ``clock/advance`` is not refused (409)."""
    served = pmac_and_trio_realtime
    script = _shell_block(ROOT / "examples" / "pmac" / "README.md")
    assert "http://127.0.0.1:8000" in script
    out = subprocess.run(["bash", "-euo", "pipefail", "-c",
                          script.replace("http://127.0.0.1:8000", served.url)],
                         cwd=ROOT, capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    docs = _json_documents(out.stdout)
    assert all("code" not in d for d in docs if isinstance(d, dict)), docs  # no error bodies
    events = docs[-1]["events"]
    starts = {e["n"]: e["t"] for e in events if e["type"] == "move_start"}
    (write,) = [e for e in events if e["type"] == "mvar"]
    assert write["sync"] is True and write["name"] == "M1"
    # TUM p250: the synchronous write lands at the first RTI at or after the move to X20 starts
    assert starts[3] <= write["t"] < starts[3] + 0.002
    assert served.client.clock("pmac").mode == "realtime"  # make run's own controller untouched
    # the README's second block, where it says: the card's own command line, then the delete
    head = script.split("curl")[0]  # S=..., B=...
    more = head + _shell_block(ROOT / "examples" / "pmac" / "README.md", 1)
    out = subprocess.run(["bash", "-euo", "pipefail", "-c",
                          more.replace("http://127.0.0.1:8000", served.url)],
                         cwd=ROOT, capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    ahead, status = _json_documents(out.stdout)
    assert ahead["error"] is None and int(ahead["reply"]) == 0
    assert status["error"] is None and status["reply"].strip()
    assert "pv" not in {c["id"] for c in served.client.controllers()}


@pytest.fixture
def pmac_and_trio_realtime():
    """What ``make run`` serves: the default controllers on a realtime clock."""
    from types import SimpleNamespace

    from motionsim.app.client import MotionSimClient
    from motionsim.app.embedded import EmbeddedService
    from motionsim.app.settings import Settings

    with EmbeddedService(Settings(port=0, pmac_port=0, trio_port=0)) as service, \
            MotionSimClient(service.url) as client:
        yield SimpleNamespace(url=service.url, client=client)
