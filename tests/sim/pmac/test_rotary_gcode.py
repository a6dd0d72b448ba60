"""G-code and subroutines in rotary buffers (issue 37 item 1), in virtual time on the event
log.

* A rotary line may call fixed programs: ``CALL{prog}[.{label}]`` (TSRM p416) and the
  machine-tool codes, ``G{data}`` = ``CALL 10n0.({data'}*1000)``, M / T / D into PROG 10n1 /
  10n2 / 10n3 (TSRM p425; TUM p328-330); the called program's ``RETURN`` comes back to the
  rest of the rotary line, then the next rotary line.
* The one-line ``IF ({condition}) {statements}`` is the only conditional a rotary buffer
  takes (PUM p162); multi-line forms are ERR003.
* A stream of G01 / G02 / G03 / G04 / G00 lines with a PROG 1000 written as the manual's
  (TUM p330: ``N01000 LINEAR RETURN``, ``N02000 CIRCLE1 RETURN``, ``N03000 CIRCLE2 RETURN``,
  ``N04000 READ(P) DWELL(Q116*1000) RET``) moves as those modes do: arcs the long or the short
  way round by their direction (CIRCLE1 clockwise, CIRCLE2 counter-clockwise, Isx13 > 0 so
  the arc is segmented along its length), G04 dwells P seconds.
"""

from __future__ import annotations

import math

import pytest

from .conftest import Rig

#: PROG 1000 as TUM p330 writes it (G00 RAPID, G01 LINEAR, G02 CIRCLE1, G03 CIRCLE2, G04 a
#: dwell of P seconds), and G90 absolute.
PROG_1000 = ["N0 RAPID RET", "N01000 LINEAR RET", "N02000 CIRCLE1 RET", "N03000 CIRCLE2 RET",
             "N04000 READ(P) DWELL(Q116*1000) RET", "N90000 ABS RET"]


def _rig() -> Rig:
    rig = Rig()
    rig.ok("&1 #1->X #2->Y")
    rig.ok("I5113=10")  # segmentation: CIRCLE moves follow the arc (TUM p 'Isx13')
    rig.rotary_setup()
    return rig


def _prog(rig: Rig, n: int, lines: list[str]) -> None:
    rig.ok(f"OPEN PROG {n} CLEAR")
    for line in lines:
        rig.ok(line)
    rig.ok("CLOSE")


def _stream(rig: Rig, lines: list[str], run_s: float = 30.0) -> None:
    rig.ok("OPEN ROT")
    for line in lines:
        rig.ok(line)
    rig.ok("CLOSE")
    rig.ok("&1 B0 R")
    rig.run_for(run_s)


def _durations(rig: Rig) -> dict[int, float]:
    start, out = {}, {}
    for t, kind, f in rig.events("move_start", "move_end"):
        if kind == "move_start":
            start[f["n"]] = t
        else:
            out[f["n"]] = (t - start[f["n"]]) * rig.period
    return out


def test_a_g_code_stream_runs_as_the_manuals_prog_1000_says():
    rig = _rig()
    _prog(rig, 1000, PROG_1000)
    _stream(rig, [
        "G90 G01 X10 Y0 F10",   # ABS, LINEAR, then the move: 10 at F10 = 1 s
        "G02 X20 Y10 I0 J10",   # clockwise round (10,10): three quarters, 15 pi / F
        "G01 X10 Y0",           # back along the chord, 10 sqrt 2 / F
        "G03 X20 Y10 I0 J10",   # counter-clockwise: one quarter, 5 pi / F
        "G04 P0.5",             # dwell 0.5 s (READ(P) -> Q116)
        "G00 X0 Y0",            # RAPID home
    ])
    assert rig.events("program_error") == []
    d = _durations(rig)
    assert sorted(d) == [1, 2, 3, 4, 5, 6]
    assert d[1] == pytest.approx(1.0, abs=0.02)
    assert d[2] == pytest.approx(15 * math.pi / 10, abs=0.05)
    assert d[3] == pytest.approx(10 * math.sqrt(2) / 10, abs=0.05)
    assert d[4] == pytest.approx(5 * math.pi / 10, abs=0.15)  # (it stops before the dwell)
    assert d[5] == pytest.approx(0.5, abs=0.01)
    assert rig.c.positions(1) == pytest.approx({"X": 0.0, "Y": 0.0})
    assert rig.c.vars.read("Q", 116, 1) == pytest.approx(0.5)
    assert {f["n"] for _, _, f in rig.events("line_calculated")} == {1, 2, 3, 4, 5, 6}


def test_tsrm_p425_code_numbers_pick_the_program_and_label():
    """G{data}: PROG 10n0, label {data'}*1000; M 10n1, T 10n2, D 10n3 (D115 is N15000 of PROG
    1013)."""
    rig = _rig()
    _prog(rig, 1000, ["N7000 P1=1 RET"])
    _prog(rig, 1001, ["N3000 P2=3 RET"])
    _prog(rig, 1002, ["N12000 P3=12 RET"])
    _prog(rig, 1013, ["N15000 P4=115 RET"])
    _stream(rig, ["G7", "M03 M1=1", "T12", "D115", "TM10 X1"], run_s=1.0)
    got = [rig.c.vars.read("P", k, 1) for k in (1, 2, 3, 4)]
    assert got == [1, 3, 12, 115]
    assert rig.c.vars.read("M", 1, 1) == 1  # an M-variable assignment stays one
    assert rig.c.positions(1)["X"] == pytest.approx(1.0)


def test_a_rotary_call_returns_to_the_next_rotary_line():
    rig = _rig()
    _prog(rig, 20, ["X3", "RET"])
    _prog(rig, 21, ["N10000 Y2", "RET"])
    # (X9 after an explicit CALL is an argument only: PROG 21 does not READ it)
    _stream(rig, ["TM100 X1", "CALL20", "X4", "CALL21.1 X9", "X5"], run_s=2.0)
    starts = [f["n"] for _, _, f in rig.events("move_start")]
    assert starts == [1, 2, 3, 4, 5]  # the called programs' moves under the calling line
    assert rig.c.positions(1) == pytest.approx({"X": 5.0, "Y": 2.0})


def test_the_one_line_if_in_a_rotary_buffer():
    rig = _rig()
    rig.ok("P1=1")
    _stream(rig, ["TM100 X1", "IF (P1=1) X5", "IF (P1=0) X7", "IF (P1=1) AND (P2=0) Y3",
                  "X8"], run_s=2.0)
    assert [f["n"] for _, _, f in rig.events("move_start")] == [1, 2, 4, 5]
    assert rig.c.positions(1) == pytest.approx({"X": 8.0, "Y": 3.0})
    # the false line is calculated too, moving nothing
    assert 3 in {f["n"] for _, _, f in rig.events("line_calculated")}


@pytest.mark.parametrize(("line", "not_simulated"), [
    ("IF (P1=1)", False), ("ENDIF", False), ("ELSE", False), ("WHILE (P1=0)", False),
    ("GOSUB10", True), ("GOTO10", True), ("RETURN", True), ("WAIT", True),
])
def test_what_a_rotary_line_refuses_changes_nothing(line, not_simulated):
    rig = _rig()
    rig.ok("OPEN ROT")
    reply = rig.cmd(line)
    assert reply.error == "ERR003"
    assert (rig.c._terminal.detail[0] == "not_simulated") is not_simulated
    assert rig.c.coord_system(1).rotary.lines_ahead == 0
    rig.ok("CLOSE")


def test_a_code_into_a_missing_program_is_a_run_time_error_and_on_line_is_err005():
    rig = _rig()
    _stream(rig, ["TM10 X1", "G01 X2"], run_s=1.0)
    (err,) = rig.events("program_error")
    assert err[2]["n"] == 2 and "PROG 1000" in err[2]["reason"]
    assert rig.cmd("G01").error == "ERR005"  # a program statement with no buffer open
