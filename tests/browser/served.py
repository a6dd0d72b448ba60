"""``motionsim serve`` as a subprocess on a free 127.0.0.1 port, and Debian's Chromium.

Shared by the browser tests (conftest.py) and ``make screenshot`` (screenshot.py).
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from contextlib import contextmanager
from typing import IO

import httpx

from tests.ports import free_port
from tests.processes import stop

#: Flags Chromium needs as root in a container (CI runs as root) and without a GPU.
CHROMIUM_ARGS = ["--no-sandbox", "--disable-dev-shm-usage", "--disable-gpu"]


def chromium_path() -> str | None:
    """Debian's Chromium (``MOTIONSIM_CHROMIUM`` overrides), or None."""
    explicit = os.environ.get("MOTIONSIM_CHROMIUM")
    if explicit:
        return explicit
    for name in ("chromium", "chromium-browser"):
        found = shutil.which(name)
        if found:
            return found
    return None


@contextmanager
def serve(timeout_s: float = 30.0) -> Iterator[str]:
    """Serve motionsim (virtual clocks, no protocol listeners) until the block ends; its URL.
    Its output goes to a temporary file (read on failure): an unread pipe could fill up."""
    port = free_port()
    with tempfile.TemporaryFile("w+") as output:
        proc = subprocess.Popen(
            [sys.executable, "-m", "motionsim", "serve", "--host", "127.0.0.1", "--port",
             str(port), "--clock", "virtual", "--pmac-port", "0", "--trio-port", "0"],
            stdout=output, stderr=subprocess.STDOUT, text=True)
        url = f"http://127.0.0.1:{port}"
        try:
            _wait_healthy(proc, url, output, timeout_s)
            yield url
        finally:
            stop(proc)


def _wait_healthy(proc: subprocess.Popen, url: str, output: IO[str], timeout_s: float) -> None:
    deadline = time.monotonic() + timeout_s
    while True:
        try:
            if httpx.get(f"{url}/health", timeout=1).status_code == 200:
                return
        except httpx.HTTPError:
            pass
        if proc.poll() is not None or time.monotonic() > deadline:
            proc.kill()
            output.seek(0)
            raise RuntimeError(f"motionsim serve did not come up on {url}:\n{output.read()}")
        time.sleep(0.1)
