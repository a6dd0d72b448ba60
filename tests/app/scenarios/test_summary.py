"""The printed summary a person reads: at most 100 columns (piped too), nothing cut off,
starvations grouped with the rows kept in metrics.json, Trio moves per axis against what was
expected, and headers that say what their latency measures."""

from __future__ import annotations

import io
import json
import subprocess
import sys
from pathlib import Path

import pytest
from motionsim.app.scenarios.model import loads_scenario
from motionsim.app.scenarios.report import report
from motionsim.app.scenarios.runner import run
from motionsim.app.scenarios.summary import WIDTH, print_summary
from rich.console import Console

from tests.app.scenarios.test_examples import EXAMPLES, run_example

BIN = Path(sys.executable).parent


def _printed(rep: dict) -> str:
    buf = io.StringIO()
    print_summary(rep, Console(file=buf, width=WIDTH, color_system=None))
    return buf.getvalue()


@pytest.mark.parametrize("name", ["rotary_breq.yaml", "tn20_stall_and_fix.yaml",
                                  "trio_feeders.yaml", "write_via_terminal.yaml"])
def test_every_line_fits_100_columns_and_no_cell_is_cut(name):
    _, rep = run_example(name)
    text = _printed(rep)
    assert max(len(line) for line in text.splitlines()) <= 100
    assert "…" not in text


def test_piped_output_of_motionsim_run_is_100_columns_wide(tmp_path):
    out = subprocess.run([str(BIN / "motionsim"), "run", str(EXAMPLES / "rotary_breq.yaml"),
                          "--out", str(tmp_path), "--no-plots"],
                         capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    lines = out.stdout.splitlines()
    assert lines[-1].startswith("simulated ")  # the closing line names the output folder
    lines = lines[:-1]
    assert max(len(line) for line in lines) <= 100
    assert max(len(line) for line in lines) > 80  # wrapped at 100, not at a pipe's 80
    assert "…" not in out.stdout


def test_starvations_are_summarised_and_every_row_is_in_metrics_json(tmp_path):
    result, rep = run_example("rotary_breq.yaml")
    slow = [s for s in rep["starvations"] if s["controller"] == "slow"]
    (group,) = [g for g in rep["starvation_summary"] if g["controller"] == "slow"]
    assert group["count"] == len(slow) > 10
    assert group["total_s"] == pytest.approx(sum(s["length_s"] for s in slow))
    assert group["longest_s"] == max(s["length_s"] for s in slow)
    assert group["first_s"] == slow[0]["start_s"] and group["last_s"] == slow[-1]["start_s"]
    text = _printed(rep)
    assert text.count("host_latency") == 2  # one table row, one diagnosis line; not 77 rows
    assert f"{len(rep['starvations'])} episodes; each one is in metrics.json" in text
    from motionsim.app.scenarios.outputs import write_outputs

    write_outputs(result, rep, tmp_path, plots=False)
    metrics = json.loads((tmp_path / "metrics.json").read_text())
    assert len(metrics["starvations"]) == len(rep["starvations"])


def test_latency_columns_say_what_they_measure():
    _, rep = run_example("rotary_breq.yaml")
    text = _printed(rep)
    assert "write reply: command → answer, mean; line wait: loaded → executed, max" in text


SKIPPING_FIX = """\
name: skipping
duration_s: 8
controllers:
  t:
    kind: trio
    axes:
      0: {speed: 100, accel: 100000, decel: 100000}
      1: {speed: 100, accel: 100000, decel: 100000}
    programs:
      SKIP: |
        FOR n=1 TO 6
          IF NTYPE AXIS(0)=0 THEN
            MOVE(10) AXIS(0)
          ENDIF
          IF NTYPE AXIS(1)=0 THEN
            MOVE(100) AXIS(1)
          ENDIF
        NEXT n
    run:
      - {program: SKIP, process: 1}
    expected_moves: {0: 6, 1: 6}
"""


def test_a_fix_that_skips_moves_does_not_read_as_a_success():
    rep = report(run(loads_scenario(SKIPPING_FIX)))
    axes = rep["controllers"]["t"]["axes"]
    assert axes[0]["moves_done"] < 6 and axes[0]["moves_planned"] == 6
    assert rep["starvations"] == []  # it never blocked ...
    text = _printed(rep)
    assert f"{axes[0]['moves_done']}/6" in text
    assert f"not every move ran: t axis 0: {axes[0]['moves_done']} of 6 moves" in text
    assert "no starvation" not in text  # ... but it is no success


def test_the_tn20_examples_skipping_fix_is_flagged_and_the_stall_ran_everything():
    _, rep = run_example("tn20_stall_and_fix.yaml")
    for axis in (0, 1):
        m = rep["controllers"]["stall"]["axes"][axis]
        assert (m["moves_done"], m["moves_planned"]) == (6, 6)
    fix = rep["controllers"]["fix"]["axes"]
    assert fix[0]["moves_done"] < 6 and fix[0]["moves_planned"] == 6
    text = _printed(rep)
    assert f"not every move ran: fix axis 0: {fix[0]['moves_done']} of 6 moves" in text
    assert "stall axis" not in "".join(line for line in text.splitlines()
                                      if line.startswith("not every move ran"))


def test_feeder_hosts_moves_are_counted_per_axis():
    _, rep = run_example("trio_feeders.yaml")
    for r in rep["controllers"].values():
        assert {a: m["moves_planned"] for a, m in r["axes"].items()} == {0: 6, 1: 6}
