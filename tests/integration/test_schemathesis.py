"""Schemathesis (pinned in the ``test`` extra) over every operation of ``/openapi.json``,
including the stateful phase, against a ``motionsim serve`` subprocess: no 5xx, every response
documented and matching its schema.

Budget: ``make test`` runs a few examples per operation within ``SCHEMATHESIS_MAX_TIME``
(default 120 s); ``make fuzz`` sets ``MOTIONSIM_FUZZ=1`` for many more.
``positive_data_acceptance`` is not checked: a schema-valid request may still name a controller
or program that does not exist, or an event type the controller never emits (404 / 422 are
the contract there).
A ``run-until`` on a realtime or host-paced clock may wait out its documented 30-s wall cap
(``wall_timeout``), so the request timeout is well above that cap.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

from tests.integration.test_clients_pmac import motionsim_serve

FUZZING = os.environ.get("MOTIONSIM_FUZZ") == "1"
CHECKS = ("not_a_server_error,status_code_conformance,content_type_conformance,"
          "response_schema_conformance,response_headers_conformance,negative_data_rejection,"
          "unsupported_method,allow_header_conformance")


def test_schemathesis_finds_no_server_error_and_no_schema_violation(tmp_path):
    exe = shutil.which("schemathesis", path=str(Path(sys.executable).parent))
    assert exe is not None, "schemathesis is in the test extra: pip install -e '.[test]'"
    examples = os.environ.get("SCHEMATHESIS_EXAMPLES", "200" if FUZZING else "3")
    max_time = os.environ.get("SCHEMATHESIS_MAX_TIME", "900" if FUZZING else "120")
    with motionsim_serve("--pmac-port", "0", "--trio-port", "0") as svc:
        cmd = [exe, "run", svc.http + "/openapi.json", "--checks", CHECKS,
               "--phases", "examples,coverage,fuzzing,stateful", "-n", examples,
               "--max-time", max_time, "--request-timeout", "75", "--workers", "1",
               "--seed", "1", "--generation-deterministic" if not FUZZING else "--no-shrink",
               "--report", "junit", "--report-dir", str(tmp_path)]
        out = subprocess.run(cmd, capture_output=True, text=True, timeout=int(max_time) + 300,
                             env={**os.environ, "NO_COLOR": "1"}, cwd=tmp_path)
        health = svc.proc.poll()
    summary = out.stdout[-6000:]
    print(next((ln for ln in out.stdout.splitlines() if "generated" in ln), "no test cases?"))
    assert health is None, "the service died under schemathesis:\n" + summary
    assert out.returncode == 0, summary
