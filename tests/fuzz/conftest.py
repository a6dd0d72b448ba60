"""Hypothesis budgets for the parser and codec fuzz targets, and the case counts.

``make test`` runs each target with the small ``test`` profile; ``make fuzz`` sets
``MOTIONSIM_FUZZ=1`` for the ``fuzz`` profile (``MOTIONSIM_FUZZ_EXAMPLES`` per target, default
20 000: with the seven targets over 10^5 cases). Every target counts the inputs it ran
(:func:`counted`); the totals are printed at the end and written to ``fuzz-counts.json``
(with ``make test``'s workers, each worker's counts are added up in the controlling process).
"""

from __future__ import annotations

import json
import os
from collections import Counter
from pathlib import Path

from hypothesis import HealthCheck, settings

FUZZING = os.environ.get("MOTIONSIM_FUZZ") == "1"
EXAMPLES = int(os.environ.get("MOTIONSIM_FUZZ_EXAMPLES", "20000")) if FUZZING else 60

settings.register_profile(
    "motionsim-fuzz", max_examples=EXAMPLES, deadline=None, derandomize=not FUZZING,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                           HealthCheck.filter_too_much], database=None)

#: cases run per target in this session
COUNTS: Counter[str] = Counter()


def counted(target: str) -> None:
    COUNTS[target] += 1


def pytest_sessionfinish(session) -> None:  # noqa: ANN001 - pytest hook
    """In a pytest-xdist worker: hand this worker's counts to the controlling process
    (tests/conftest.py ``pytest_testnodedown`` adds them up there)."""
    out = getattr(session.config, "workeroutput", None)
    if out is not None:
        out["fuzz_counts"] = dict(COUNTS)


def summary(terminalreporter) -> None:  # noqa: ANN001 - pytest's reporter
    """The counts at the end of the run (tests/conftest.py ``pytest_terminal_summary``)."""
    if not COUNTS:
        return
    total = sum(COUNTS.values())
    terminalreporter.write_line(f"fuzz cases: {total} in total")
    for target, n in sorted(COUNTS.items()):
        terminalreporter.write_line(f"  {target}: {n}")
    if FUZZING:
        Path("fuzz-counts.json").write_text(json.dumps({"total": total, **COUNTS}, indent=1))
