"""``motionsim check`` report details: the count of lines refused after a failed OPEN in the
singular, an OPEN named only in a comment is no OPEN, and a Trio ``REM`` line is all comment
(TSRM: ERR005 "command allowed only with a buffer open"; Trio BASIC: REM starts a remark)."""

from __future__ import annotations

import pytest
from motionsim.app import check
from motionsim.app.cli import cli
from motionsim.sim.pmac.card.error_codes import MEANINGS
from typer.testing import CliRunner

RUNNER = CliRunner()


def _run(*args: str):
    return RUNNER.invoke(cli, ["check", *args])


def test_one_more_line_refused_after_a_failed_open_is_singular(tmp_path):
    path = tmp_path / "prog.pmc"
    path.write_text("&1 OPEN ROT\nINC\nX1\nCLOSE\n")
    lines = _run(str(path)).output.splitlines()
    assert lines[1:] == [f"{path}:2:1: error: ERR005 {MEANINGS['ERR005']}",
                         "  … and 1 more line refused because OPEN at line 1 failed"]


@pytest.mark.parametrize("line", ["ENABLE PLC 99 ; OPEN it later",
                                  'ENABLE PLC 99 CMD"OPEN PROG 1"'])
def test_an_open_in_a_comment_or_string_of_a_refused_line_is_not_a_failed_open(tmp_path, line):
    path = tmp_path / "plc.pmc"
    path.write_text(f"{line}\nX5\n")
    lines = _run(str(path)).output.splitlines()
    assert lines == [
        f"{path}:1:12: error: ERR003 {MEANINGS['ERR003']}: no PLC 99 (0..31)",
        f"{path}:2:1: error: ERR005 {MEANINGS['ERR005']}"]  # its own error, no OPEN cause


def test_an_indented_rem_line_is_a_remark_whatever_words_or_bytes_it_holds(tmp_path):
    """No not_simulated warning for the TRON in the remark, and no encoding finding for its
    byte above 0x7F (only program text must be ASCII)."""
    path = tmp_path / "main.bas"
    path.write_text("  REM TRON here, 5 \u00b5m\nTRON\n", encoding="latin-1")
    lines = _run("--model", "mc4xx", str(path)).output.splitlines()
    assert lines == [f"{path}:2:1: warning: not_simulated TRON is a Trio BASIC command that "
                     "is not simulated"]


def test_has_word_finds_a_command_word_not_text_inside_a_string():
    assert check._has_word("&1 OPEN ROT", "OPEN")
    assert not check._has_word('ENABLE PLC 99 CMD"OPEN PROG 1"', "OPEN")
    assert not check._has_word("ENABLE PLC 3", "OPEN")


def test_a_tripped_watchdog_ends_the_check_with_one_error_at_column_1(tmp_path):
    """A PLC 0 too long for the real-time interrupt starves the background: "the watchdog timer
    will trip, shutting down the card" and the CPU "will not communicate" (TSRM p57, TUM p215;
    seed 003). The lines sent meanwhile are not answered; the first line the tripped card is
    sent is one error (code ``watchdog``, column 1: no column of the line is at fault) and
    nothing after it is checked."""
    path = tmp_path / "starve.pmc"
    path.write_text("OPEN PLC 0 CLEAR\n" + "P10=P10+1\n" * 500 + "CLOSE\nENABLE PLC 0\n"
                    + "P1=1\n" * 8)
    (found,) = check.check_file(path)
    assert (found.severity, found.code, found.column) == ("error", "watchdog", 1)
    assert 503 < found.line <= 511 and found.text == "P1=1"
    assert "watchdog has tripped" in found.message


def test_a_trio_error_without_its_source_text_shows_the_files_line(tmp_path):
    """A compile error that names its line but carries no text is shown with that line of
    the file as read (the report's ``text``); a line outside the file shows nothing."""
    from motionsim.sim.errors import ParseError

    class Card:  # a controller whose errors carry a line number only
        def store_program(self, name: str, text: str) -> None:
            raise AssertionError("nothing to store: no library, no INCLUDE")

        def check_program(self, name: str, text: str) -> list[ParseError]:
            return [ParseError(f"at {n}", line=n, column=2) for n in (1, 2, 3, 4, 0)]

    path = tmp_path / "prog.bas"
    path.write_text("a = 1\nb = 2\nc = 3\n")
    found = check.check_trio(path, Card())
    assert [(f.line, f.column, f.text) for f in found] == [
        (1, 2, "a = 1"), (2, 2, "b = 2"), (3, 2, "c = 3"), (4, 2, ""), (1, 2, "a = 1")]
