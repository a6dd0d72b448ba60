"""``motionsim replay`` of a ``--record`` transcript cut by ``kill -9`` while a request was in
flight (issue 23, item 6): every complete exchange replays and matches, the session that was
open is reported as incomplete, and the exit status is 0; a last line cut short is skipped.
"""

from __future__ import annotations

import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import httpx

from tests.integration.test_clients_pmac import ROOT, _packet, _read_reply, motionsim_serve

GETRESPONSE = 0xBF


def _replay(path: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "motionsim", "replay",
                           str(path)], cwd=ROOT, capture_output=True, text=True, timeout=120)


def _crash_recording(path: Path) -> None:
    """Two answered requests, then one in flight when the service is killed with SIGKILL: a
    stalled background (a fault) leaves its answer pending on the virtual clock, which nobody
    advances."""
    with motionsim_serve("--pmac-port", "auto", "--trio-port", "0", "--record",
                         str(path)) as svc:
        sock = socket.create_connection(("127.0.0.1", svc.listening["pmac"]), timeout=10)
        for command in (b"P1=5", b"P1"):
            sock.sendall(_packet(0x40, GETRESPONSE, command))
            assert _read_reply(sock).endswith(b"\x06")
        added = httpx.post(f"{svc.http}/controllers/pmac/faults", timeout=10,
                           json={"kind": "stall", "duration_ms": 100000})
        assert added.status_code == 201
        sock.sendall(_packet(0x40, GETRESPONSE, b"I17"))
        time.sleep(0.5)                      # recorded as "in"; its answer is being held
        svc.proc.send_signal(signal.SIGKILL)
        svc.proc.wait(timeout=10)
        sock.close()


def test_a_transcript_cut_by_kill_9_mid_request_replays_its_complete_exchanges(tmp_path):
    path = tmp_path / "wire.jsonl"
    _crash_recording(path)
    lines = path.read_text().splitlines()
    assert '"kind":"close"' not in lines[-1] and '"kind":"in"' in lines[-1]
    done = _replay(path)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "1/1 sessions match" in done.stdout
    assert "incomplete" in done.stdout and "in flight" in done.stdout


def test_a_last_line_cut_short_is_skipped_and_reported(tmp_path):
    path = tmp_path / "wire.jsonl"
    _crash_recording(path)
    with path.open("a") as f:
        f.write('{"kind":"in","session":1,"t":0.5,"wall":17')  # a write the kill cut
    done = _replay(path)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "cut short" in done.stdout and "incomplete" in done.stdout


def test_a_changed_answer_in_a_cut_transcript_still_fails(tmp_path):
    path = tmp_path / "wire.jsonl"
    _crash_recording(path)
    text = path.read_text()
    path.write_text(text.replace('"data":"5', '"data":"6', 1))
    done = _replay(path)
    assert done.returncode == 1 and "FAIL" in done.stdout
