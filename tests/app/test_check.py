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
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
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


# -- files as the downloaders read them (issue 36) -----------------------------------------

def test_cp1252_and_shift_jis_comments_are_bytes_the_downloader_strips(tmp_path):
    """A downloader sends bytes and strips comments: Windows-1252 (``é`` = 0xE9) and
    Shift-JIS (``軸`` = 0x8E 0xB2) remarks never stop a check; the command text is checked."""
    west = tmp_path / "west.pmc"
    west.write_bytes("; réglage de l'axe 1\nI130=1000 ; gain proportionnel, réglé\nX10\n"
                     .encode("cp1252"))
    east = tmp_path / "east.plc"
    east.write_bytes("; 軸1の設定\nOPEN PLC 3 CLEAR\nP1=1 ; 原点復帰\nCLOSE\n"
                     .encode("shift_jis"))
    assert b"\xe9" in west.read_bytes() and b"\x8e\xb2" in east.read_bytes()
    result = _run(str(west), str(east))
    assert result.exit_code == 1, result.output  # the X10 only: no buffer open (ERR005)
    assert result.output.splitlines() == [
        f"{west}:3:1: error: ERR005 {MEANINGS['ERR005']}"]


def test_a_non_ascii_byte_in_the_command_text_is_an_error_at_its_line_and_column(tmp_path):
    path = tmp_path / "bad.pmc"
    path.write_bytes("P1=1\nP2=3\xb5 ; µ in the comment is fine\nP3=4\n".encode("cp1252"))
    result = _run("--format", "json", str(path))
    assert result.exit_code == 1
    (found,) = json.loads(result.output)
    assert (found["line"], found["column"], found["code"]) == (2, 5, "encoding")
    assert "0xB5" in found["message"] and "ASCII" in found["message"]
    trio = tmp_path / "bad.bas"
    trio.write_bytes(b"MOVE(10) ' \x88\xda\x93\xae\nPRINT \"caf\xe9\"\n")  # SJIS, cp1252
    result = _run(str(trio))
    assert result.exit_code == 1
    assert result.output.startswith(f"{trio}:2:11: error: encoding byte 0xE9 is not ASCII")


def test_trio_comments_may_hold_shift_jis(tmp_path):
    path = tmp_path / "jp.bas"
    path.write_bytes("' 軸の原点復帰\nBASE(0)\nMOVE(10) ' 移動\nWAIT IDLE\n".encode("shift_jis"))
    assert _run(str(path)).exit_code == 0


def test_pewin_include_angle_brackets_beside_the_file_and_with_dash_i(tmp_path):
    """PEWIN's ``#include <header.h>`` (``[INF]`` C's form) is found beside the including
    file and in each ``-I DIR``; ``#include "x"`` as before."""
    (tmp_path / "axes.h").write_text("#define JOG_SPEED I122\n")
    lib = tmp_path / "lib"
    lib.mkdir()
    (lib / "plc.h").write_text("#Define FLAG P100\n")
    top = tmp_path / "setup.pmc"
    top.write_text("#include <axes.h>\n#include <plc.h>\nJOG_SPEED=10\nFLAG=1\nFLAG=(\n")
    result = _run(str(top))
    assert result.exit_code == 1
    assert result.output.startswith(f"{top}:2:11: error: include cannot find 'plc.h'")
    findings = check_file(top, include=[lib])
    assert [(f.line, f.column, f.code, f.text) for f in findings] == [
        (5, 7, "ERR003", "P100=(")]  # 7: in "P100=(", after expansion


def test_pewin_comments_and_defines_in_any_case(tmp_path):
    """PEWIN / PComm32 ``[INF]``: ``//`` and ``/* */`` are comments (a block may span lines),
    ``#define`` / ``#Define`` / ``#DEFINE`` define macros replacing whole names only."""
    path = tmp_path / "pewin.pmc"
    path.write_text("/* motor set-up\n   written for PEWIN32PRO */\n#Define AX P10\n"
                    "#DEFINE GAIN 1000\n#define MAX_V I116\nI130=GAIN // gain\n"
                    "AX=1 /* inline */ MAX_V=50\nMAXAX=1\n")
    result = _run("--dialect", "pewin", str(path))
    # MAXAX is not AX: left whole, and the card refuses the unknown word
    assert result.exit_code == 1, result.output
    (line,) = result.output.splitlines()
    assert line.startswith(f"{path}:8:1: error: ERR003")
    assert _run(str(path)).output == result.output  # auto detects PEWIN from // and #Define
    diamond = _run("--dialect", "diamond", str(path))  # the same file under Diamond's rules
    assert diamond.output.count("error:") > 1


def test_msi_macros_from_dash_d_and_an_undefined_one_named_at_its_column(tmp_path):
    """EPICS ``msi``: ``$(NAME)`` / ``${NAME}`` / ``$(NAME=default)``; an undefined macro is
    an error naming it, every later use counted under the first."""
    path = tmp_path / "axis.pmc.template"
    path.write_text("I$(AXIS)30=$(GAIN=1000)\nI${AXIS}31=10\nP$(BASE)=1\nP$(BASE)1=2\n"
                    "P$(BASE)2=3\n")
    result = _run("--kind", "pmac", "-D", "AXIS=1", str(path))
    assert result.exit_code == 1
    assert result.output.splitlines() == [
        f"{path}:3:2: error: macro $(BASE) is not defined (-D BASE=VALUE gives it a value)",
        "  … and 2 more lines refused because $(BASE) is not defined"]
    assert _run("--kind", "pmac", "-D", "AXIS=1", "-D", "BASE=20", str(path)).exit_code == 0
    result = _run("--kind", "pmac", "-D", "AXIS", str(path))
    assert result.exit_code == 2 and "NAME=VALUE" in result.output


def test_one_refused_open_is_one_error_and_a_count_of_its_err005_lines(tmp_path):
    """TSRM: a buffer command with no buffer open answers ERR005. After a refused OPEN every
    line meant for the buffer gets it; they are counted under the OPEN, up to its CLOSE."""
    body = "".join(f"P{n}=P{n}+1 X{n}\n" for n in range(1, 1301))
    path = tmp_path / "prog.pmc"
    path.write_text(f"; no rotary defined\nI5=2\n&1 OPEN ROT\nINC\n{body}CLOSE\nX5\n")
    result = _run(str(path))
    assert result.exit_code == 1
    assert result.output.splitlines() == [
        f"{path}:3:1: error: ERR003 {MEANINGS['ERR003']}: no rotary buffer is defined",
        f"{path}:4:1: error: ERR005 {MEANINGS['ERR005']}",
        "  … and 1 300 more lines refused because OPEN at line 3 failed",
        f"{path}:1306:1: error: ERR005 {MEANINGS['ERR005']}"]  # after CLOSE: its own error
    found = json.loads(_run("--format", "json", str(path)).output)
    assert [(f["line"], f["more"], f["cause"]) for f in found] == [
        (3, 0, ""), (4, 1300, "OPEN at line 3 failed"), (1306, 0, "")]


def test_refusals_after_a_missing_include_are_counted_under_it(tmp_path):
    top = tmp_path / "plc.pmc"
    top.write_text('#include "defs.pmc"\nOPEN PLC 3 CLEAR\n'
                   + "".join(f"MY_FLAG{n}=1\n" for n in range(200)) + "CLOSE\n")
    result = _run(str(top))
    assert result.exit_code == 1
    lines = result.output.splitlines()
    assert lines[0].startswith(f"{top}:1:11: error: include cannot find 'defs.pmc'")
    assert lines[1].startswith(f"{top}:3:")
    assert lines[2] == (f"  … and 199 more lines refused because the #include at {top}:1 "
                        "was not found")
    assert len(lines) == 3


def test_check_dir_checks_a_tree_in_one_run_with_each_convention(tmp_path):
    """``motionsim check DIR``: every PMAC and Trio file below DIR, one grouped report, an
    included file checked where it is included (not alone), exit 1 on an error."""
    (tmp_path / ".git").mkdir()
    (tmp_path / ".git" / "junk.pmc").write_text("X10\n")
    pewin = tmp_path / "lab_a"
    pewin.mkdir()
    (pewin / "io.pmc").write_text("// inputs\nM1->Y:$078802,0\nM1=1\n")  # included below
    (pewin / "main.pmc").write_bytes('#include "io.pmc"\n#Define ON 1\nM1=ON ; 入力\n'
                                     .encode("shift_jis"))
    diamond = tmp_path / "lab_b"
    diamond.mkdir()
    (diamond / "gains.pmc").write_bytes(b"#define KP I130\nKP=1000 ; r\xe9glage\nKP=(\n")
    msi = tmp_path / "lab_c"
    msi.mkdir()
    (msi / "axis.pmc").write_text("I$(AXIS=1)22=10\n")
    (msi / "pick.bas").write_text("BASE(0)\nMOVE(10\n")
    (tmp_path / "README.md").write_text("not a program\n")
    result = _run(str(tmp_path))
    assert result.exit_code == 1, result.output
    assert result.output.splitlines() == [
        f"{diamond / 'gains.pmc'}:3:7: error: ERR003 {MEANINGS['ERR003']}: expected a value"
        " (after macro expansion)",
        f"{msi / 'pick.bas'}:2:8: error: parse_error expected ')', found 'end of line'"]


def test_diamond_dialect_sends_what_dls_pmaclib_sends(tmp_path):
    """The ``diamond`` convention is Diamond's tool's, line for line (its output with
    ``debug`` markers, comments and blank lines aside), on a file it can read."""
    from motionsim.app.pmac_download import SourceLine, expand

    ClsPmacParser = pytest.importorskip("dls_pmaclib.dls_pmcpreprocessor").ClsPmacParser
    (tmp_path / "inc").mkdir()
    (tmp_path / "inc" / "axis.pmc").write_text("#define AXIS 1\n#define MOTOR #AXIS\n"
                                               "MOTOR J+ ; jog\n\tI1AXIS0=1\n")
    top = tmp_path / "top.pmc"
    top.write_text('; header\n#define SPEED P100\n#define SPEEDY P200\n#include "axis.pmc"\n'
                   "SPEED=5 ; fast\nSPEEDY=6\n\n  P1=SPEED*2\r\n#DEFINE X Q1\nX=1\n")
    want = [line for line in ClsPmacParser([str(tmp_path / "inc")]).parse(str(top)) if line]
    got = [s.text for s in expand(top, "diamond", [tmp_path / "inc"])
           if isinstance(s, SourceLine)]
    assert got == want


def test_the_readme_sample_is_what_check_prints():
    """README "Check a program without a card": the command, run from the repository root
    on the shipped examples, prints the sample's lines (a line ending ``...`` is cut there)."""
    readme = (ROOT / "README.md").read_text()
    section = readme[readme.index("## Check a program without a card"):]
    block = re.search(r"```sh\n(.*?)```", section, re.S).group(1).splitlines()
    (command,) = [line for line in block if line and not line.startswith("#")]
    want = [line[2:] for line in block if line.startswith("# ")]
    args = command.split()
    assert args[:2] == ["motionsim", "check"]
    done = subprocess.run([str(Path(sys.executable).parent / "motionsim"), *args[1:]],
                          cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert done.returncode == 1, done.stderr
    got = done.stdout.splitlines()
    assert len(got) == len(want), done.stdout
    for line, sample in zip(got, want, strict=True):
        if sample.endswith(" ..."):
            assert line.startswith(sample[:-4]), (line, sample)
        else:
            assert line == sample


def test_cp1252_ellipsis_and_form_feed_do_not_break_a_line(tmp_path):
    """Only CR, LF and CR LF end a line: Windows-1252's ``…`` (0x85, Unicode's NEL once read
    byte for byte) and a form feed inside a comment leave the line numbers alone."""
    path = tmp_path / "nel.pmc"
    path.write_bytes(b"P1=1 ; wait\x85 then go\r\nP2=2 ; page\x0c two\r\nX1\r\n")
    result = _run(str(path))
    assert result.output.splitlines() == [f"{path}:3:1: error: ERR005 {MEANINGS['ERR005']}"]


def test_a_file_in_another_encoding_is_one_error_and_a_count(tmp_path):
    """Shift-JIS command text (a file whose remarks lack ``;``): the first byte above 0x7F is
    the error, the other lines are counted under it."""
    path = tmp_path / "jp.pmc"
    path.write_bytes(b"P1=1\n" + "".join(f"原点{n}\n" for n in range(40))
                     .encode("shift_jis"))
    result = _run(str(path))
    assert result.exit_code == 1
    assert result.output.splitlines() == [
        f"{path}:2:1: error: encoding byte 0x8C is not ASCII: a PMAC's command text is ASCII "
        "(only a comment may hold other bytes); the line is not sent",
        "  … and 39 more lines refused because they hold bytes above 0x7F outside a comment"]


@settings(max_examples=40, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.binary(max_size=300), suffix=st.sampled_from([".pmc", ".bas"]),
       dialect=st.sampled_from(["auto", "pewin", "diamond", "msi"]))
def test_any_bytes_are_checked_never_crash(tmp_path, data, suffix, dialect):
    """Whatever a file holds, ``check`` answers findings (exit 0 or 1), never a crash."""
    path = tmp_path / f"any{suffix}"
    path.write_bytes(data)
    result = _run("--dialect", dialect, str(path))
    assert result.exit_code in (0, 1), (result.output, result.exception)
    assert result.exception is None or isinstance(result.exception, SystemExit)


def test_dash_d_predefines_a_pewin_or_diamond_macro(tmp_path):
    path = tmp_path / "axis.pmc"
    path.write_text("#define GAIN_I I130\nGAIN_I=KP\n")
    assert _run(str(path)).exit_code == 1  # KP unknown to the card
    assert _run("-D", "KP=1000", str(path)).exit_code == 0
    assert _run("--dialect", "pewin", "-D", "KP=1000", str(path)).exit_code == 0


def test_a_tree_reports_every_file_it_can_and_exits_2_for_one_it_cannot(tmp_path):
    """Exit status as for files: 2 when a file cannot be checked (here a link to nothing,
    which a folder walk lists rather than skipping), after the findings of those that could.
    ``--model`` names the Trio model: the tree's PMAC file is still checked, on the Turbo PMAC."""
    (tmp_path / "a.pmc").write_text("P1=1\nOPEN PROG 1\nX10 FOO\nCLOSE\n")
    (tmp_path / "b.bas").write_text("MOVE(1\n")
    (tmp_path / "c.pmc").symlink_to(tmp_path / "missing.pmc")
    result = _run("--model", "mc4xx", str(tmp_path))
    assert result.exit_code == 2
    assert f"{tmp_path / 'a.pmc'}:3:6: error: ERR003" in result.output
    assert f"{tmp_path / 'b.bas'}:1:7: error: parse_error" in result.output
    assert f"{tmp_path / 'c.pmc'}: [Errno 2] No such file or directory" in result.output
    assert "--model" not in result.output


def test_model_names_a_trio_model_so_kind_pmac_with_a_model_is_refused(tmp_path):
    path = tmp_path / "a.pmc"
    path.write_text("P1=1\n")
    result = _run("--kind", "pmac", "--model", "mc4xx", str(path))
    assert result.exit_code == 2 and "--model names a Trio model" in result.output


def test_the_pre_commit_hook_matches_the_suffixes_check_dir_reads():
    from motionsim.app.check import PMAC_SUFFIXES, TRIO_SUFFIXES

    (hook,) = yaml.safe_load((ROOT / ".pre-commit-hooks.yaml").read_text())
    for suffix in (*PMAC_SUFFIXES, *TRIO_SUFFIXES):
        assert re.search(hook["files"], f"prog{suffix}"), suffix


def test_a_trio_project_folder_stores_the_programs_a_program_includes(tmp_path):
    """TRM ``INCLUDE "name"`` (MC4xx): the included program must be on the controller; the
    programs of the folder a program includes are stored first, so a project checks clean;
    without them the include is refused."""
    (tmp_path / "INIT.BAS").write_bytes("feed = 10 ' 送り速度\n".encode("shift_jis"))
    (tmp_path / "MAIN.BAS").write_text('INCLUDE "INIT"\nBASE(0)\nMOVE(feed)\n')
    result = _run("--model", "mc4xx", str(tmp_path))
    assert result.exit_code == 0, result.output
    alone = tmp_path / "solo"
    alone.mkdir()
    (alone / "MAIN.BAS").write_text('INCLUDE "INIT"\nBASE(0)\nMOVE(feed)\n')
    result = _run("--model", "mc4xx", str(alone))
    assert result.exit_code == 1
    assert 'INCLUDE "INIT": there is no program INIT' in result.output


def test_auto_reads_the_convention_from_the_included_files_too(tmp_path):
    """A download has one convention: a top file written like Diamond's that includes a
    PEWIN-style file (``//`` comments) is downloaded as PEWIN would."""
    (tmp_path / "code.pmc").write_text("// set-up\nP1=1 // first\nP2=2\n")
    top = tmp_path / "top.pmc"
    top.write_text('; top\n#define N 3\n#include "code.pmc"\nP3=N\n')
    assert _run(str(top)).output == ""
    assert "ERR003" in _run("--dialect", "diamond", str(top)).output


def test_msi_include_and_substitute_lines(tmp_path):
    """``msi``'s own directives: ``substitute "NAME=VALUE,..."`` sets values for the lines
    after it, ``include "file"`` inserts a template (searched as ``#include`` is)."""
    (tmp_path / "motor.tmpl").write_text("I$(M)30=$(KP)\nI$(M)31=(\n")
    top = tmp_path / "axes.pmc"
    top.write_text('substitute "M=1,KP=1000"\ninclude "motor.tmpl"\n'
                   'substitute "M=2"\ninclude "motor.tmpl"\n')
    findings = check_file(top, dialect="msi")
    assert [(Path(f.file).name, f.line, f.code, f.text) for f in findings] == [
        ("motor.tmpl", 2, "ERR003", "I131=("), ("motor.tmpl", 2, "ERR003", "I231=(")]


def test_pewin_conditionals_take_or_skip_lines(tmp_path):
    """PEWIN ``[INF]`` (C's ``#ifdef``): a block not taken is neither sent nor checked, so
    its refusals and bytes do not count; ``-D`` defines a name for ``#ifdef``; a missing
    ``#endif`` is an error at its ``#ifdef``."""
    path = tmp_path / "opt.pmc"
    path.write_bytes(b"#ifdef BRAKE\nM1=1\n#else\nP1=(\n\xe9\n#endif\n#ifndef BRAKE\nP2=2\n"
                     b"#endif\n#define X P3\n#undef X\n#ifdef X\nP4=(\n#endif\n")
    result = _run("--format", "json", str(path))
    assert [(f["line"], f["code"]) for f in json.loads(result.output)] == [
        (4, "ERR003"), (5, "encoding")]
    assert _run("-D", "BRAKE=1", str(path)).exit_code == 0
    open_ = tmp_path / "open.pmc"
    open_.write_text("#ifndef A\nP1=1\n")
    assert _run(str(open_)).output.startswith(
        f"{open_}:1:1: error: directive #ifdef / #ifndef without its #endif")
