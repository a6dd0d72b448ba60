"""``make docker-test``'s verdict on compose's output (tools/docker_test.py), without an engine:
the client's JSON summary is found in either Compose's prefixed output, and a run that did not
stream every line, never waited for BREQ, did not finish or starved fails."""

from __future__ import annotations

import json
import sys

import pytest

from tests.app.test_cli import ROOT

sys.path.insert(0, str(ROOT / "tools"))
try:
    import docker_test
finally:
    sys.path.pop(0)

GOOD = {"controller": "compose-client-1", "lines_sent": 2005, "breq_waits": 7, "starved": 0,
        "ran_out_at": 40.1, "program": {"state": "waiting", "line": None}}


@pytest.mark.parametrize("prefix", [
    "client_1     | ",                      # Compose v1 (docker-compose)
    "client-1  | ",                         # Compose v2 (docker compose)
    "\x1b[36mclient_1     |\x1b[0m ",       # colours left on
])
def test_the_clients_summary_is_read_from_either_composes_output(prefix):
    out = "\n".join(["motionsim_1  | motionsim listening http://0.0.0.0:8000",
                     f"{prefix}{json.dumps(GOOD)}",
                     "motionsim-docker-test_client_1 exited with code 0"])
    assert docker_test.client_summary(out) == GOOD


def test_no_summary_is_a_failure():
    with pytest.raises(docker_test.Failed, match="no JSON summary"):
        docker_test.client_summary('motionsim_1  | {"status": "ok"}\n')


def test_a_good_summary_passes():
    docker_test.check_summary(GOOD, 2000)


@pytest.mark.parametrize(("change", "says"), [
    ({"lines_sent": 1500}, "lines_sent 1500 < the 2000 lines"),
    ({"breq_waits": 0}, "no BREQ wait"),
    ({"program": {"state": "running"}}, "did not run to its end"),
    ({"starved": 1}, "starved 1"),
])
def test_a_summary_that_shows_a_problem_fails_naming_it(change, says):
    with pytest.raises(docker_test.Failed, match=says):
        docker_test.check_summary({**GOOD, **change}, 2000)


def test_the_client_line_count_is_the_compose_files():
    text = (ROOT / "docker-compose.yml").read_text()
    assert docker_test.compose_client_lines(text) == 2000
    with pytest.raises(docker_test.Failed, match="no \"--lines\""):
        docker_test.compose_client_lines(text.replace('"--lines"', '"--count"'))
