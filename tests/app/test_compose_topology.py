"""docker-compose.yml without Docker: the same two services as real processes on 127.0.0.1.

The ``motionsim`` service runs ``motionsim serve`` (here on free ports and a virtual clock so
the test is fast); the ``client`` service runs ``examples/compose_client.py``, which streams a
program into the PMAC's rotary buffer over REST, obeying BREQ.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import httpx
import yaml

from tests.app.test_cli import ENV, ROOT, _serve, _stop

COMPOSE = yaml.safe_load((ROOT / "docker-compose.yml").read_text())


def test_compose_declares_the_service_and_the_example_client():
    services = COMPOSE["services"]
    assert services["motionsim"]["command"][:2] == ["motionsim", "serve"]
    assert "healthcheck" in services["motionsim"]
    assert services["client"]["depends_on"]["motionsim"]["condition"] == "service_healthy"
    assert services["client"]["command"][1] == "examples/compose_client.py"
    assert (ROOT / services["client"]["command"][1]).is_file()


def test_dockerfile_is_slim_non_root_with_a_health_check():
    text = (ROOT / "Dockerfile").read_text()
    assert "FROM python:3.11-slim" in text
    assert "\nUSER motionsim" in text
    assert "HEALTHCHECK" in text and "/health" in text


def test_the_example_client_streams_a_program_through_a_served_motionsim():
    served = _serve("--port", "0", "--clock", "virtual", "--pmac-port", "auto",
                    "--trio-port", "auto")
    try:
        assert served.url, served.lines
        client = subprocess.run(
            [sys.executable, str(Path("examples") / "compose_client.py"), "--url", served.url,
             "--lines", "300", "--batch", "25"],
            capture_output=True, text=True, timeout=120, env=ENV, cwd=ROOT)
        assert client.returncode == 0, client.stderr
        summary = json.loads(client.stdout.splitlines()[-1])
        assert summary["lines_sent"] == 305
        assert summary["breq_waits"] > 0           # the 600-word buffer filled up
        assert summary["program"]["state"] == "waiting"  # ran out of lines at the end
        assert summary["starved"] == 0                    # virtual time: the host never lags
        with httpx.Client(base_url=served.url, trust_env=False) as http:
            loaded = http.get("/controllers/pmac/events",
                              params={"type": "line_loaded", "limit": 10_000}).json()["events"]
        assert [e["n"] for e in loaded] == list(range(1, 306))
    finally:
        _stop(served)
