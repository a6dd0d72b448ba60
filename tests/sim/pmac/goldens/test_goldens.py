"""Golden event logs: today's PMAC example scenarios and scripted lookahead runs (cases.py)
give byte-identical event logs. They pin behaviour through refactors of the move planner.

Regenerate (only when a change of behaviour is intended and reviewed):
``MOTIONSIM_REGEN_GOLDENS=1 .venv/bin/pytest tests/sim/pmac/goldens``.
"""

from __future__ import annotations

import difflib
import gzip
import os
from pathlib import Path

import pytest
from motionsim.app.scenarios.model import load_scenario
from motionsim.app.scenarios.runner import run

from tests.sim.pmac.goldens.cases import CASES, record

HERE = Path(__file__).resolve().parent
DATA = HERE / "data"
EXAMPLES = HERE.parents[3] / "examples" / "scenarios"
REGEN = os.environ.get("MOTIONSIM_REGEN_GOLDENS") == "1"

#: The example scenarios with a PMAC coordinate system running rotary programs.
SCENARIOS = (
    "breq_missed", "calc_behind", "lookahead_breaks", "m1_sync", "plc0_watchdog",
    "pr_polling", "rotary_breq", "write_via_terminal",
)  # fmt: skip


def _check(name: str, text: str) -> None:
    path = DATA / f"{name}.jsonl.gz"
    if REGEN:
        DATA.mkdir(exist_ok=True)
        path.write_bytes(gzip.compress(text.encode(), mtime=0))
        return
    want = gzip.decompress(path.read_bytes()).decode()
    if text != want:
        diff = difflib.unified_diff(
            want.splitlines(), text.splitlines(), "golden", "now", n=1, lineterm=""
        )
        pytest.fail(f"{name}: the event log changed:\n" + "\n".join(list(diff)[:40]))


@pytest.mark.parametrize("name", SCENARIOS)
def test_example_scenario_event_log_is_byte_identical(name):
    _check(f"scenario_{name}", run(load_scenario(EXAMPLES / f"{name}.yaml")).to_jsonl())


@pytest.mark.parametrize("name", sorted(CASES))
def test_scripted_lookahead_run_event_log_and_profile_are_byte_identical(name):
    _check(f"case_{name}", record(name))
