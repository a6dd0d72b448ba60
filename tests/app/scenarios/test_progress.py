"""A long run's analysis and its files show progress (issue 36 item 3: 195 000 events were
49 s of silence after the progress bar). The CLI draws these reports as Rich bars."""

from __future__ import annotations

from motionsim.app.scenarios.model import loads_scenario
from motionsim.app.scenarios.outputs import write_outputs
from motionsim.app.scenarios.report import report
from motionsim.app.scenarios.runner import run

from .test_remote import SHORT


def test_the_analysis_and_the_files_report_their_progress(tmp_path):
    scn = loads_scenario(SHORT)
    result = run(scn)
    seen: list[tuple[float, float]] = []
    rep = report(result, progress=lambda done, total: seen.append((done, total)))
    assert seen == [(0, 1), (1, 1)]  # before and after each controller's analysis
    wrote: list[tuple[float, float]] = []
    paths = write_outputs(result, rep, tmp_path, plots=False,
                          progress=lambda done, total: wrote.append((done, total)))
    assert wrote == [(1, 4), (2, 4), (3, 4), (4, 4)]
    assert sorted(paths) == ["events.csv", "events.jsonl", "metrics.json"]
