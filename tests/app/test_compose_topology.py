"""docker-compose.yml without Docker: the same two services as real processes on 127.0.0.1.

The ``motionsim`` service runs ``motionsim serve`` (here on free ports and a virtual clock so
the test is fast); the ``client`` service runs ``examples/compose_client.py``, which streams a
program into the PMAC's rotary buffer over REST, obeying BREQ.
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import httpx
import yaml

from tests.app.test_cli import ENV, ROOT, _serve, _stop
from tests.app.test_image_entrypoint import image_healthcheck

COMPOSE = yaml.safe_load((ROOT / "docker-compose.yml").read_text())
README = (ROOT / "README.md").read_text()


def test_compose_declares_the_service_and_the_example_client():
    services = COMPOSE["services"]
    assert services["motionsim"]["command"][:2] == ["motionsim", "serve"]
    assert "healthcheck" in services["motionsim"]
    assert services["client"]["depends_on"]["motionsim"]["condition"] == "service_healthy"
    assert services["client"]["command"][1] == "examples/compose_client.py"
    assert (ROOT / services["client"]["command"][1]).is_file()


def test_compose_v2_builds_the_client_instead_of_pulling_an_image_of_that_name():
    """An ``image:`` without ``build:`` is pulled from a registry by Compose v2; the client
    builds from the same Dockerfile (its layers are the motionsim service's)."""
    client = COMPOSE["services"]["client"]
    assert client.get("build") == COMPOSE["services"]["motionsim"]["build"] == "."
    assert "image" not in client or "build" in client


def test_compose_documents_exit_code_from_client():
    for text in ((ROOT / "docker-compose.yml").read_text(), (ROOT / "README.md").read_text()):
        assert "docker compose up --build --exit-code-from client" in text


def test_the_readme_says_what_to_type_with_either_compose():
    """Compose v2 is the ``docker compose`` plugin, v1 Debian's ``docker-compose`` (bookworm has
    no v2 package): the Docker section's first block gives the command for each."""
    section = README.split("\n## Docker\n", 1)[1].split("\n## ", 1)[0]
    block = re.search(r"```sh\n(.*?)```", section, re.S)[1]
    assert [line.split("#")[0].strip() for line in block.splitlines()] == [
        "docker compose up --build --exit-code-from client",
        "docker-compose up --build --exit-code-from client"]
    assert "make docker-test" in section


def test_the_health_checks_follow_the_configured_port():
    """Image and compose run the same health check module, which reads ``MOTIONSIM_PORT`` —
    the variable the image's ``motionsim serve`` takes its port from (that they import the
    installed package where Docker runs them: tests/app/test_image_entrypoint.py)."""
    text = (ROOT / "Dockerfile").read_text()
    assert COMPOSE["services"]["motionsim"]["healthcheck"]["test"] == ["CMD", *image_healthcheck()]
    assert image_healthcheck()[-2:] == ["-m", "motionsim.app.healthcheck"]
    assert "MOTIONSIM_PORT=8000" in text
    assert COMPOSE["services"]["motionsim"]["environment"]["MOTIONSIM_PORT"] == "8000"


def test_dockerfile_is_slim_non_root_with_a_health_check():
    """Built on Debian's slim image (a registry's, or the one tools/docker_base_image.sh makes
    from Debian packages under the same tag), run as its own user."""
    text = (ROOT / "Dockerfile").read_text()
    assert re.search(r"^FROM debian:[a-z]+-slim\b", text, re.M)
    assert "\nUSER motionsim" in text
    assert "HEALTHCHECK" in text


def _client(url: str, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, str(Path("examples") / "compose_client.py"), "--url", url, *args],
        capture_output=True, text=True, timeout=120, env=ENV, cwd=ROOT)


def test_the_example_client_streams_a_program_through_a_served_motionsim():
    served = _serve("--port", "0", "--clock", "virtual", "--pmac-port", "auto",
                    "--trio-port", "auto")
    try:
        assert served.url, served.lines
        client = _client(served.url, "--clock", "virtual", "--lines", "300", "--batch", "25",
                         "--keep")
        assert client.returncode == 0, client.stderr
        summary = json.loads(client.stdout.splitlines()[-1])
        assert summary["lines_sent"] == 305
        assert summary["breq_waits"] > 0           # the 600-word buffer filled up
        assert summary["program"]["state"] == "waiting"  # ran out of lines at the end
        assert summary["starved"] == 0                    # virtual time: the host never lags
        with httpx.Client(base_url=served.url, trust_env=False) as http:
            loaded = http.get(f"/controllers/{summary['controller']}/events",
                              params={"type": "line_loaded", "limit": 10_000}).json()["events"]
        assert [e["n"] for e in loaded] == list(range(1, 306))
    finally:
        _stop(served)


def test_the_client_runs_again_and_again_against_a_running_server():
    """Each run streams into a controller of its own and deletes it afterwards; with
    ``--controller`` it reuses one, clearing what the last run left (program, buffer)."""
    served = _serve("--port", "0", "--clock", "virtual", "--pmac-port", "0",
                    "--trio-port", "0")
    try:
        with httpx.Client(base_url=served.url, trust_env=False) as http:
            before = {c["id"] for c in http.get("/controllers").json()}
            seen = set()
            for _ in range(2):
                run = _client(served.url, "--clock", "virtual", "--lines", "100")
                assert run.returncode == 0, run.stderr
                seen.add(json.loads(run.stdout.splitlines()[-1])["controller"])
            assert len(seen) == 2
            assert {c["id"] for c in http.get("/controllers").json()} == before
            http.patch("/controllers/pmac/clock", json={"mode": "virtual"}).raise_for_status()
            for _ in range(2):
                run = _client(served.url, "--controller", "pmac", "--lines", "100")
                assert run.returncode == 0, run.stderr
                assert json.loads(run.stdout.splitlines()[-1])["lines_sent"] == 105
    finally:
        _stop(served)


def test_the_client_exit_status_says_what_failed():
    unreachable = _client("http://127.0.0.1:9", "--wait-healthy-s", "0.5")
    assert unreachable.returncode == 2
    served = _serve("--port", "0", "--clock", "virtual", "--pmac-port", "0", "--trio-port", "0")
    try:
        refused = _client(served.url, "--clock", "virtual", "--words", "0")
        assert refused.returncode == 1
        assert "422" in refused.stderr
    finally:
        _stop(served)
