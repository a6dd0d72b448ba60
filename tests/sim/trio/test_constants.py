"""Constants are constants (spec trio.md §11.10): PI, TRUE, FALSE, ON, OFF and LAST_AXIS at the
command line and in programs, and no Trio keyword is ever read as a local variable worth 0."""

from __future__ import annotations

import math

import pytest
from motionsim.sim.errors import ParseError

from tests.sim.trio.conftest import fields, make, run_to


@pytest.mark.parametrize(("name", "reply"), [
    ("PI", "3.1416"), ("TRUE", "-1.0000"), ("FALSE", "0.0000"), ("ON", "1.0000"),
    ("OFF", "0.0000"), ("LAST_AXIS", "7.0000"),
])
@pytest.mark.parametrize("model", ["mc2xx", "mc4xx"])
def test_p11_10_constants_at_the_command_line(model, name, reply):
    assert make(model=model).terminal(f"? {name}").reply == reply


def test_p11_10_last_axis_is_the_highest_axis_number_of_the_controller():
    assert make(axes=4).terminal("? LAST_AXIS").reply == "3.0000"


def test_tj2p_167_pi_in_a_program_is_the_constant_at_the_models_word():
    c = make(model="mc4xx")
    c.store_program("R", "circum = 100\nVR(0) = circum / (2 * PI)\nVR(1) = LAST_AXIS\n")
    c.run_program("R", 1)
    run_to(c, 0.1)
    assert c.vr[0] == pytest.approx(100 / (2 * math.pi), rel=1e-15)
    assert c.vr[1] == 7.0


@pytest.mark.parametrize(("text", "column", "what"), [
    ("PI = 3\n", 1, "PI is a constant"),
    ("x = 1 : TRUE = 0\n", 9, "TRUE is a constant"),
    ("LAST_AXIS = 2\n", 1, "LAST_AXIS cannot be written"),
    ("FOR ON = 1 TO 3\nNEXT\n", 5, "ON is a Trio BASIC keyword"),
    ("LOADED = 1\n", 1, "LOADED is a Trio BASIC keyword"),
    ("IDLE = 1\n", 1, "IDLE cannot be written"),
    ("x = STEP + 1\n", 5, "STEP is a Trio BASIC keyword"),
])
def test_p11_10_a_keyword_is_never_a_local_variable(text, column, what):
    c = make(model="mc4xx")
    with pytest.raises(ParseError) as err:
        c.store_program("K", text)
    assert err.value.details["column"] == column and what in err.value.message
    assert c.program_names() == []


CAM_PROFILE = """\
' a cycloidal cam of 1000 edges over 40 points, linked to 80 units of axis 1
npoints = 40
FOR i = 0 TO npoints
  TABLE(i, 1000 * (i / npoints - SIN(2 * PI * i / npoints) / (2 * PI)))
NEXT i
BASE(0)
CAMBOX(0, npoints, 1, 80, 1)
BASE(1)
MOVE(80)
WAIT IDLE
WAIT IDLE AXIS(0)
VR(0) = DPOS AXIS(0)
"""


def test_trm_p8_19_camfile_computed_with_pi_runs_and_ends_where_the_table_ends():
    c = make(model="mc4xx")
    c.store_program("CAMS", CAM_PROFILE)
    c.run_program("CAMS", 1)
    run_to(c, 1.0)
    (_t, f), = fields(c, "process", process=1, state="stopped")
    assert "error" not in f  # no "Divide by zero": PI is not a local worth 0
    assert c.table[20] == pytest.approx(500.0)  # the midpoint of a cycloid
    assert c.vr[0] == pytest.approx(1000.0)
    assert [f["mtype"] for _t, f in fields(c, "move_start", axis=0)] == [20]  # CAMBOX
