"""``motionsim check FILE...``: the lines a fresh card would refuse, without a card.

The verdicts are the card's own (the terminal the service runs, the Trio compiler
``PUT /programs`` runs): a test below sends the same lines to a served controller's REST
terminal and gets the same answers. Error codes and meanings: TSRM I6 error table (ERR003
syntax, ERR005 buffer command with no buffer open, ERR007 a buffer already open).
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest
import yaml
from motionsim.app.check import check_file
from motionsim.app.cli import cli
from motionsim.sim.pmac.card.error_codes import MEANINGS
from typer.testing import CliRunner

from tests.app.test_cli import ROOT

RUNNER = CliRunner()

MOTION_PROGRAM = """\
; homing helpers and a move program
I5=2
OPEN PROG 20 CLEAR
INC LINEAR
TA100 TS0 F50
X10 Y$$
DWELL 100
CLOSE
OPEN PROG 21
OPEN PLC 3 CLEAR
CLOSE
X5
CHECKSUM
"""


def _run(*args: str):
    return RUNNER.invoke(cli, ["check", *args])


def test_tsrm_i6_each_refused_line_is_file_line_column_errnnn_meaning(tmp_path):
    path = tmp_path / "motion.pmc"
    path.write_text(MOTION_PROGRAM)
    result = _run(str(path))
    assert result.exit_code == 1, result.output
    lines = result.output.splitlines()
    want = [(6, 5, "ERR003"), (10, 1, "ERR007"), (12, 1, "ERR005")]
    assert len(lines) == len(want) + 1
    for text, (n, column, code) in zip(lines, want, strict=False):
        # the controller's own detail may follow the manual's meaning
        assert text.startswith(f"{path}:{n}:{column}: error: {code} {MEANINGS[code]}"), text
    assert lines[-1] == (f"{path}:13:1: warning: not_simulated CHECKSUM is a valid Turbo PMAC "
                         "command that motionsim does not simulate (docs/pmac.md lists what "
                         "is simulated)")


def test_a_file_with_only_not_simulated_lines_passes_with_warnings(tmp_path):
    path = tmp_path / "ok.pmac"
    path.write_text("P1=1\nPASSWORD=abc\n")
    result = _run(str(path))
    assert result.exit_code == 0
    assert result.output == (f"{path}:2:1: warning: not_simulated PASSWORD is a valid Turbo "
                             "PMAC command that motionsim does not simulate (docs/pmac.md "
                             "lists what is simulated)\n")


def test_pmc_defines_and_includes_are_expanded_by_diamonds_preprocessor(tmp_path):
    """``#define`` / ``#include`` go through ``dls_pmaclib.dls_pmcpreprocessor``; a refused
    line in an included file is reported at that file's own line and column (a leading tab
    counted), a line changed by a macro says so."""
    (tmp_path / "gains.pmc").write_text("I130=1000 ; proportional gain\n\tI131=1O\n")
    top = tmp_path / "axis.pmc"
    top.write_text('#define SPEED P100\n#include "gains.pmc"\nSPEED=5\nSPEED=(\n')
    findings = check_file(top)
    assert [(Path(f.file).name, f.line, f.column, f.code) for f in findings] == [
        ("gains.pmc", 2, 8, "ERR003"), ("axis.pmc", 4, 7, "ERR003")]  # 7: in "P100=("
    assert "(after macro expansion)" in findings[1].message
    assert findings[1].text == "P100=("


def test_trio_not_simulated_keywords_warn_and_the_compile_error_fails(tmp_path):
    path = tmp_path / "pick.bas"
    path.write_text("BASE(0)\nTRON\nMOVE(10)\nIF IN(3) THEN\n  MOVE(5\nENDIF\n")
    result = _run(str(path))
    assert result.exit_code == 1
    assert result.output.splitlines() == [
        f"{path}:2:1: warning: not_simulated TRON is a Trio BASIC command that is not simulated",
        f"{path}:5:9: error: parse_error expected ')', found 'end of line'",
    ]
    good = tmp_path / "good.bas"
    good.write_text("BASE(0)\nMOVE(10)\nWAIT IDLE\n")
    assert _run(str(good)).exit_code == 0


def test_json_format_lists_every_finding_for_ci_annotations(tmp_path):
    path = tmp_path / "motion.pmc"
    path.write_text(MOTION_PROGRAM)
    result = _run("--format", "json", str(path))
    assert result.exit_code == 1
    found = json.loads(result.output)
    assert [(f["line"], f["column"], f["severity"], f["code"]) for f in found] == [
        (6, 5, "error", "ERR003"), (10, 1, "error", "ERR007"), (12, 1, "error", "ERR005"),
        (13, 1, "warning", "not_simulated")]
    assert found[0]["text"] == "X10 Y$$"


def test_a_file_that_cannot_be_checked_names_itself(tmp_path):
    path = tmp_path / "p.bas"
    path.write_text("MOVE(1)\n")
    result = _run("--model", "NOPE", str(path))
    assert result.exit_code == 2
    assert str(path) in result.output and "model must be one of" in result.output


def test_the_verdicts_are_the_served_terminals(motionsim, tmp_path):
    """Each line sent to a served PMAC's REST terminal gets the error ``check`` reports."""
    motionsim.create_controller("pmac", id="card", clock="virtual")
    path = tmp_path / "motion.pmc"
    path.write_text(MOTION_PROGRAM)
    checked = {f.line: f.code if f.severity == "error" else "ERR003" for f in check_file(path)}
    served = {}
    for n, text in enumerate(MOTION_PROGRAM.splitlines(), 1):
        if text.strip() and not text.startswith(";"):
            error = motionsim.terminal("card", text).error
            if error:
                served[n] = error
    # a not-simulated line answers the wire's ERR003 (check: a warning, code not_simulated)
    assert served == checked == {6: "ERR003", 10: "ERR007", 12: "ERR005", 13: "ERR003"}


def test_pre_commit_hook_runs_the_installed_command(tmp_path):
    """``.pre-commit-hooks.yaml`` at the root: pre-commit installs the repository and runs
    ``entry`` with the staged files that match ``files``."""
    (hook,) = yaml.safe_load((ROOT / ".pre-commit-hooks.yaml").read_text())
    assert hook["id"] == "motionsim-check" and hook["language"] == "python"
    assert all(re.search(hook["files"], name) for name in ("a.pmc", "b.plc", "c.bas"))
    assert not re.search(hook["files"], "README.md")
    bad = tmp_path / "bad.pmc"
    bad.write_text("X10\n")
    entry = hook["entry"].split()
    assert entry[0] == "motionsim"
    done = subprocess.run([str(Path(sys.executable).parent / entry[0]), *entry[1:], str(bad)],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 1
    assert done.stdout.startswith(f"{bad}:1:1: error: ERR005")
    assert "motionsim-check" in (ROOT / "README.md").read_text()


@pytest.mark.parametrize("kind", ["pmac", "trio"])
def test_kind_option_overrides_the_suffix(tmp_path, kind):
    path = tmp_path / "prog.txt"
    path.write_text("MOVE(10)\n" if kind == "trio" else "P1=1\n")
    assert _run("--kind", kind, str(path)).exit_code == 0


def test_a_missing_include_is_an_error_at_its_line_and_dash_i_finds_it(tmp_path):
    """The preprocessor leaves a missing ``#include`` out with only a log line; check
    reports it at the include's line, and ``-I DIR`` adds a folder to search."""
    top = tmp_path / "axis.pmc"
    top.write_text('; axis set-up\n#include "gains.pmc"\nP1=1\n')
    result = _run(str(top))
    assert result.exit_code == 1
    assert result.output.startswith(f"{top}:2:11: error: include cannot find 'gains.pmc'")
    lib = tmp_path / "lib"
    lib.mkdir()
    (lib / "gains.pmc").write_text("I130=1000\n")
    assert _run("-I", str(lib), str(top)).exit_code == 0
