"""Error trapping and multi-way branches (spec trio.md §11.3): ``ON BASICERROR GOTO`` with
RUN_ERROR / ERROR_LINE in the handler (TRM p. 8-118), ``ON expr GOSUB`` / ``ON expr GOTO``
(TJ2P5-138)."""

from __future__ import annotations

import pytest

from tests.sim.trio.conftest import fields, make, run_to

HANDLED = """\
ON BASICERROR GOTO error_routine
VR(1) = 1
VR(2) = 10 / VR(0)
VR(1) = 2
STOP
error_routine:
VR(10) = RUN_ERROR
VR(11) = ERROR_LINE
PRINT "error "; RUN_ERROR[0]; " in line "; ERROR_LINE[0]
"""


def test_trm_p8_118_a_run_time_error_with_a_handler_continues_at_its_label():
    c = make()
    c.store_program("H", HANDLED)
    c.run_program("H", 2)
    run_to(c, 0.1)
    (t, trapped), = fields(c, "basic_error")
    assert trapped == {"process": 2, "line": 3, "run_error": 1, "error": "Divide by zero",
                       "handler_line": 7}
    assert t == pytest.approx(2 * 100e-6)  # line 3 is the third statement
    stopped = fields(c, "process", process=2, state="stopped")
    assert len(stopped) == 1 and "error" not in stopped[0][1] and stopped[0][1]["line"] == 9
    assert (c.vr[1], c.vr[10], c.vr[11]) == (1.0, 1.0, 3.0)
    assert c.unread_output("t") == ["error 1 in line 3"]  # no %[Process ...] line
    assert c.terminal("? RUN_ERROR PROC(2)").reply == "1.0000"


def test_p11_3_without_a_handler_the_error_stops_the_process_as_before():
    c = make()
    c.store_program("H", HANDLED.replace("ON BASICERROR GOTO error_routine", "VR(9) = 0"))
    c.run_program("H", 2)
    run_to(c, 0.1)
    assert fields(c, "basic_error") == []
    (_t, f), = fields(c, "process", process=2, state="stopped")
    assert f["line"] == 3 and f["error"] == "%[Process 2:Line 3] - Divide by zero"


def test_p11_3_an_error_inside_the_handler_stops_the_process():
    c = make()
    c.store_program("H", HANDLED + "VR(12) = VR(-1)\nVR(13) = 1\n")
    c.run_program("H", 2)
    run_to(c, 0.1)
    assert len(fields(c, "basic_error")) == 1
    (_t, f), = fields(c, "process", process=2, state="stopped")
    assert f["line"] == 10 and "VR index out of range" in f["error"]
    assert c.vr[13] == 0.0
    assert c.terminal("? ERROR_LINE PROC(2)").reply == "10.0000"


def test_p11_3_the_handler_sees_run_error_31_when_another_program_stops_it():
    c = make()
    c.store_program("AUTOM", """\
ON BASICERROR GOTO error_routine
WHILE TRUE
  VR(1) = VR(1) + 1
WEND
error_routine:
IF RUN_ERROR <> 31 THEN
  VR(2) = 99
ELSE
  VR(2) = RUN_ERROR
ENDIF
""")
    c.store_program("MAIN", 'WA(5)\nSTOP "AUTOM"\nVR(3) = 1\n')
    c.run_program("AUTOM", 3)
    c.run_program("MAIN", 1)
    run_to(c, 0.1)
    (t, f), = fields(c, "basic_error")
    assert f["run_error"] == 31 and f["process"] == 3
    assert t == pytest.approx(0.005 + 100e-6)  # MAIN's line 2 runs after WA(5)
    assert c.vr[2] == 31.0 and c.vr[3] == 1.0
    (_t, stopped), = fields(c, "process", process=3, state="stopped")
    assert "error" not in stopped


def test_p11_3_on_basicerror_is_refused_at_the_command_line():
    c = make()
    r = c.terminal("ON BASICERROR GOTO x")
    assert r.error is not None and "label 'X' is not defined" in r.error


@pytest.mark.parametrize(("value", "expected"), [(1, 10.0), (2, 20.0), (3, 30.0), (2.9, 20.0),
                                                 (0, 0.0), (4, 0.0), (-1, 0.0)])
def test_tj2p5_138_on_gosub_picks_the_label_and_out_of_range_goes_on(value, expected):
    c = make()
    c.store_program("G", f"""\
ON {value} GOSUB a, b, c
VR(2) = 1
STOP
a:
VR(1) = 10 : RETURN
b:
VR(1) = 20 : RETURN
c:
VR(1) = 30 : RETURN
""")
    c.run_program("G", 1)
    run_to(c, 0.1)
    assert (c.vr[1], c.vr[2]) == (expected, 1.0)
    assert "error" not in fields(c, "process", process=1, state="stopped")[0][1]


def test_tj2p5_138_on_goto_out_of_range_is_an_error():
    c = make()
    c.store_program("G", "k = 2\nON k GOTO a, b\na:\nVR(1) = 1\nb:\nVR(2) = 2\n"
                         "ON k + 1 GOTO a, b\n")
    c.run_program("G", 1)
    run_to(c, 0.1)
    assert (c.vr[1], c.vr[2]) == (0.0, 2.0)
    (_t, f), = fields(c, "process", process=1, state="stopped")
    assert f["line"] == 7 and "ON..GOTO value 3 is outside 1..2" in f["error"]


def test_p11_3_on_basicerror_run_again_rearms_the_handler_for_the_next_error():
    c = make()
    c.store_program("R", """\
start:
ON BASICERROR GOTO recover
REPEAT
  VR(1) = VR(1) + 1
  VR(2) = 1 / (3 - VR(1)) + 1 / (6 - VR(1))
UNTIL VR(1) >= 7
STOP
recover:
VR(3) = VR(3) + 1
GOTO start
""")
    c.run_program("R", 1)
    run_to(c, 0.1)
    assert [f["line"] for _t, f in fields(c, "basic_error")] == [5, 5]  # VR(1) = 3, then 6
    assert (c.vr[1], c.vr[2], c.vr[3]) == (7.0, -1.25, 2.0)
    assert "error" not in fields(c, "process", process=1, state="stopped")[0][1]
