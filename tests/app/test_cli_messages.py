"""The CLI's messages as a user reads them: one line naming the place of a mistake, progress on
a terminal, the command's own wall time, outputs never overwritten silently, ``--open``
without a display, and log lines that name their controller."""

from __future__ import annotations

import logging
import os
import pty
import re
import select
import subprocess
import time
from pathlib import Path

import simpy
from motionsim.app.cli import cli
from motionsim.app.clock import RealtimeClock
from motionsim.app.scenarios.model import load_scenario
from motionsim.app.scenarios.runner import run
from motionsim.sim.events import EventLog
from typer.testing import CliRunner

from tests.app.test_cli import ENV, MOTIONSIM, ROOT

SCENARIO = ROOT / "examples" / "scenarios" / "m1_sync.yaml"
OTHER = ROOT / "examples" / "scenarios" / "pr_polling.yaml"


def _invoke(*args: str, env: dict[str, str] | None = None):
    return CliRunner().invoke(cli, list(args), env=env)


# -- serve --config --------------------------------------------------------------------------


def test_a_yaml_syntax_error_is_one_line_file_line_column(tmp_path):
    path = tmp_path / "motionsim.yaml"
    path.write_text("clock: {mode: virtual\ncontrollers: []\n")
    result = _invoke("serve", "--config", str(path))
    assert result.exit_code == 2
    assert result.stderr.splitlines() == [
        f"{path}:2:12: not valid YAML: expected ',' or '}}', but got ':'"]


def test_a_json_syntax_error_is_one_line_file_line_column(tmp_path):
    path = tmp_path / "motionsim.json"
    path.write_text('{"clock": {"mode": "virtual",}}')
    result = _invoke("serve", "--config", str(path))
    assert result.exit_code == 2
    assert result.stderr.splitlines() == [
        f"{path}:1:30: not valid JSON: Expecting property name enclosed in double quotes"]


def test_a_refused_setting_names_the_line_it_is_written_on(tmp_path):
    path = tmp_path / "motionsim.yaml"
    path.write_text("clock: {mode: virtual}\ncontrollers:\n  - {id: p, kind: pmac}\n"
                    "  - id: q\n    kind: pmac\n    colour: red\n")
    result = _invoke("serve", "--config", str(path))
    assert result.exit_code == 2
    assert result.stderr.splitlines() == [
        f"{path}:6: controllers[1].colour: Extra inputs are not permitted"]


def test_an_unknown_pmac_config_key_lists_the_known_ones(tmp_path):
    path = tmp_path / "motionsim.yaml"
    path.write_text("controllers:\n  - {id: p, kind: pmac, config: {i16: 5, bogus: 1}}\n"
                    "pmac_port: 0\ntrio_port: 0\n")
    result = _invoke("serve", "--config", str(path), "--port", "0")
    assert result.exit_code == 2
    message = result.stderr.strip()
    assert message.startswith(f"{path}:2: controllers[0].config.bogus: unknown PMAC config key "
                              "'bogus'; known: ")
    for key in ("servo_hz", "i8", "i10", "background_cycles", "i0 .. i8191"):
        assert key in message


# -- run and sweep ---------------------------------------------------------------------------


def test_run_progress_slices_leave_the_event_log_unchanged():
    """Progress is reported as simulated time passes; the run it reports on is the same run,
    event for event, as one without progress."""
    seen: list[float] = []
    with_progress = run(load_scenario(SCENARIO), progress=lambda t, total: seen.append(t))
    without = run(load_scenario(SCENARIO))
    assert with_progress.to_jsonl() == without.to_jsonl()
    assert seen == sorted(seen) and seen[-1] == with_progress.t_end == 1.5
    assert len(seen) >= 100


def test_run_shows_rich_progress_on_a_terminal(tmp_path):
    """stderr on a pseudo-terminal: Rich draws the bar (simulated seconds of the total)."""
    master, slave = pty.openpty()
    proc = subprocess.Popen([str(MOTIONSIM), "run", str(SCENARIO), "--no-plots", "--out",
                             str(tmp_path / "o")], stdout=subprocess.PIPE, stderr=slave,
                            env={**ENV, "TERM": "xterm", "COLUMNS": "100"}, cwd=ROOT)
    os.close(slave)
    drawn = b""
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline:
        ready, _, _ = select.select([master], [], [], 0.5)
        if ready:
            try:
                chunk = os.read(master, 65536)
            except OSError:
                break
            if not chunk:
                break
            drawn += chunk
        elif proc.poll() is not None:
            break
    out = proc.communicate(timeout=60)[0].decode()
    os.close(master)
    assert proc.returncode == 0
    assert re.search(rb"run m1-sync.*\d+\.\d{3} / 1\.500 simulated s", drawn), drawn[-500:]
    assert "simulated s" not in out  # the bar is on stderr, transient; stdout stays a report


def test_the_closing_line_gives_the_commands_wall_time(tmp_path):
    t0 = time.perf_counter()
    result = _invoke("run", str(SCENARIO), "--no-plots", "--out", str(tmp_path / "o"))
    measured = time.perf_counter() - t0
    assert result.exit_code == 0, result.output
    m = re.search(r"simulated 1\.500 s in ([\d.]+) s wall \(duration; the simulation itself "
                  r"([\d.]+) s\)", result.stdout)
    assert m, result.stdout
    command, simulation = float(m[1]), float(m[2])
    assert simulation < command <= measured


def test_two_scenarios_into_one_out_folder_are_refused_naming_force(tmp_path):
    out = tmp_path / "o"
    assert _invoke("run", str(SCENARIO), "--no-plots", "--out", str(out)).exit_code == 0
    before = (out / "metrics.json").read_text()
    refused = _invoke("run", str(OTHER), "--no-plots", "--out", str(out))
    assert refused.exit_code == 2
    assert refused.stderr.strip() == (f"motionsim: {out} holds a run of scenario m1-sync; "
                                      "choose another --out, or pass --force to overwrite it")
    assert (out / "metrics.json").read_text() == before
    forced = _invoke("run", str(OTHER), "--no-plots", "--out", str(out), "--force")
    assert forced.exit_code == 0
    assert '"scenario": "pr-polling"' in (out / "metrics.json").read_text()


def test_the_same_scenario_again_says_it_replaces_its_earlier_run(tmp_path):
    out = tmp_path / "o"
    assert _invoke("run", str(SCENARIO), "--no-plots", "--out", str(out)).exit_code == 0
    again = _invoke("run", str(SCENARIO), "--no-plots", "--out", str(out))
    assert again.exit_code == 0
    assert f"motionsim: replacing the earlier run of m1-sync in {out}" in again.stderr


def test_open_without_a_display_says_where_the_plots_are(tmp_path, monkeypatch):
    monkeypatch.setattr("sys.platform", "linux")
    out = tmp_path / "o"
    result = _invoke("run", str(SCENARIO), "--out", str(out), "--open",
                     env={"DISPLAY": "", "WAYLAND_DISPLAY": ""})
    assert result.exit_code == 0
    assert f"no display to show the plots on; they are in {out.resolve()}:" in result.stderr
    listed = re.findall(r"^  (\S+\.png)$", result.stderr, re.M)
    assert listed and all(Path(p).is_file() for p in listed)


def test_sweep_errors_name_the_scenario_file(tmp_path):
    unknown = _invoke("sweep", str(SCENARIO), "-g", "nope=1,2", "--workers", "1")
    assert unknown.exit_code == 2
    assert unknown.stderr.startswith(f"motionsim: {SCENARIO}: nope: ")
    bad_seed = _invoke("sweep", str(SCENARIO), "-g", "seed=1:x", "--workers", "1", "--out",
                       str(tmp_path / "s"))
    assert bad_seed.exit_code == 1
    assert f"first: {SCENARIO}: seed: '1:x' is not an integer" in bad_seed.stderr
    no_metric = _invoke("sweep", str(SCENARIO), "-g", "seed=1,2", "--workers", "1",
                        "--metric", "nope", "--out", str(tmp_path / "m"))
    assert no_metric.stderr.startswith(f"motionsim: {SCENARIO}: no metric 'nope'")


# -- the service's log -----------------------------------------------------------------------


def test_realtime_clock_behind_names_the_controller(caplog):
    env = simpy.Environment()
    clock = RealtimeClock(env, log=EventLog(env, "pmac-east", 100_000))
    env.timeout(0.05)          # an event due at 0.05 s, not yet processed
    clock._anchor_wall -= 0.3  # while the schedule says 0.3 s: 0.25 s behind
    with caplog.at_level(logging.WARNING):
        clock._check_lag()
    (record,) = caplog.records
    assert re.fullmatch(r"controller pmac-east: realtime clock behind by 0\.2\d\d s \(factor 1\)",
                        record.getMessage())
