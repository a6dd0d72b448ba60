"""Servers the benches measure, each in its own process on 127.0.0.1: ``motionsim serve`` on a
free port, and the bare references (a plain FastAPI app on uvicorn, ...). Each is stopped
when its ``with`` block ends."""

from __future__ import annotations

import re
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

BIN = Path(sys.executable).parent
_URL = re.compile(r"listening (http://127\.0\.0\.1:\d+)")


@contextmanager
def process(argv: list[str], deadline_s: float = 60.0) -> Iterator[str]:
    """Start ``argv``; yields the ``http://127.0.0.1:PORT`` URL it prints (``listening URL``)."""
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        end, url, seen = time.monotonic() + deadline_s, None, []
        while url is None and time.monotonic() < end:
            line = proc.stdout.readline()
            if not line:
                break
            seen.append(line)
            m = _URL.search(line)
            url = m.group(1) if m else None
        if url is None:
            raise RuntimeError(f"{argv[0]} did not start: {''.join(seen)[-2000:]}")
        _wait_accepting(url, end)
        yield url
    finally:
        proc.terminate()
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


def _wait_accepting(url: str, end: float) -> None:
    host, port = url.removeprefix("http://").split(":")
    while True:
        try:
            socket.create_connection((host, int(port)), timeout=1).close()
            return
        except OSError:
            if time.monotonic() > end:
                raise
            time.sleep(0.05)


def motionsim(*args: str) -> Iterator[str]:
    """``motionsim serve`` with a virtual clock, no TCP listeners, on a free port."""
    return process([str(BIN / "motionsim"), "serve", "--port", "0", "--clock", "virtual",
                    "--pmac-port", "0", "--trio-port", "0", *args])


def bare_fastapi() -> Iterator[str]:
    """``bench/bare_fastapi.py`` on uvicorn: the same body shapes, no simulation."""
    return process([sys.executable, str(Path(__file__).with_name("bare_fastapi.py"))])
