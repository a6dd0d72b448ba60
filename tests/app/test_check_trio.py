"""``motionsim check`` on Trio programs (issue 32, compile errors and the check tool): every
error it can go on past is reported, one line each with line and column; an ``INCLUDE "NAME"``
is satisfied by ``NAME.bas`` given on the same command line or found with ``-I``; ``.bal``
BASIC libraries given or found there make their FUNCTIONs known.
"""

from __future__ import annotations

import json

from motionsim.app.check import check_file
from motionsim.app.cli import cli
from motionsim.sim.trio import TrioController
from typer.testing import CliRunner

RUNNER = CliRunner()

INITIALISE = "' named inputs and VRs\nestop_in = 7\ncount_vr = 20\n"
LIBRARY = "FUNCTION clamp(v, lo, hi AS FLOAT) AS FLOAT\n  IF v > hi THEN RETURN hi\n" \
          "  RETURN v\nENDFUNC\n"
MAIN = """\
INCLUDE "INITIALISE"
VR(count_vr) = clamp(estop_in, 0, 5)
x = (1
TRON
FOR i = 1 TO 3
NEXT j
y = clamp(1)
GOTO nowhere
"""


def _check(*args: str):
    return RUNNER.invoke(cli, ["check", "--model", "mc4xx", *args])


def test_every_recoverable_error_is_reported_with_its_line_and_column(tmp_path):
    (tmp_path / "INITIALISE.bas").write_text(INITIALISE)
    (tmp_path / "MOTION.bal").write_text(LIBRARY)
    main = tmp_path / "main.bas"
    main.write_text(MAIN)
    result = _check(str(main), str(tmp_path / "INITIALISE.bas"), str(tmp_path / "MOTION.bal"))
    assert result.exit_code == 1, result.output
    assert result.output.splitlines() == [
        f"{main}:3:7: error: parse_error expected ')', found 'end of line'",
        f"{main}:4:1: warning: not_simulated TRON is a Trio BASIC command that is not simulated",
        f"{main}:6:1: error: parse_error NEXT J does not match FOR I",
        f"{main}:7:1: error: parse_error CLAMP takes 3 arguments, got 1",
        f"{main}:8:1: error: parse_error label 'NOWHERE' is not defined",
    ]


def test_include_and_libraries_are_found_with_dash_i(tmp_path):
    lib = tmp_path / "lib"
    lib.mkdir()
    (lib / "initialise.BAS").write_text(INITIALISE)
    (lib / "motion.bal").write_text(LIBRARY)
    main = tmp_path / "main.bas"
    main.write_text('INCLUDE "INITIALISE"\nVR(count_vr) = clamp(estop_in, 0, 5)\n')
    assert _check(str(main)).exit_code == 1  # nothing to satisfy it
    result = _check("-I", str(lib), str(main))
    assert result.exit_code == 0, result.output
    assert result.output == ""


def test_a_missing_include_says_how_to_give_it(tmp_path):
    main = tmp_path / "main.bas"
    main.write_text('INCLUDE "INITIALISE"\nVR(0) = 1\n')
    result = _check("--format", "json", str(main))
    assert result.exit_code == 1
    (finding,) = json.loads(result.output)
    assert (finding["line"], finding["column"], finding["severity"]) == (1, 1, "error")
    assert finding["message"] == ('INCLUDE "INITIALISE": there is no program INITIALISE (give '
                                  "INITIALISE.bas on the command line, or its folder with -I "
                                  "DIR)")


def test_an_included_file_that_does_not_compile_is_an_error_at_the_include(tmp_path):
    (tmp_path / "INITIALISE.bas").write_text("estop_in = (7\n")
    main = tmp_path / "main.bas"
    main.write_text('VR(0) = 1\nINCLUDE "INITIALISE"\n')
    findings = check_file(main, "trio", "mc4xx", siblings=[main, tmp_path / "INITIALISE.bas"])
    assert [(f.line, f.column, f.severity) for f in findings][0] == (2, 10, "error")
    assert "INITIALISE.bas does not compile (line 1: expected ')'" in findings[0].message


def test_a_library_file_is_checked_as_a_library(tmp_path):
    bal = tmp_path / "tools.bal"
    bal.write_text("FUNCTION f()\n  GOTO x\nENDFUNC\nVR(0) = 1\n")
    findings = check_file(bal, model="mc4xx")
    assert [(f.line, f.column) for f in findings] == [(4, 1)]
    assert "outside a FUNCTION" in findings[0].message


def test_check_program_stores_nothing_and_lists_errors_in_line_order():
    c = TrioController("c", {"model": "mc4xx"})
    errors = c.check_program("P", "IF 1 THEN\nVR(0) = (\nWHILE 1\n")
    assert [(e.details["line"], e.details["column"]) for e in errors] == [(1, 1), (2, 10),
                                                                           (3, 1)]
    assert [e.message for e in errors][1:] == ["expected a value, found 'end of line'",
                                               "WHILE without WEND"]
    assert c.program_names() == []
