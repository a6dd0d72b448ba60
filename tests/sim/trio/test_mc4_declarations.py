"""MC4xx / MC6xx declarations as real programs write them (issue 32 item 1): DIM with an
initial value, several names on one DIM line, two-dimensional arrays, CONSTANT lines in their
bare and expression forms, and how many characters of a name count.

Sources: spec trio.md §11.4 (DIM, CONSTANT: MC4 help not reachable, forms ``[BK]`` / from real
programs), §2.1 and §2.2 (TJ1P-26: a label's first 15 characters are significant, a local
variable's first 16). Each construct runs in virtual time; each has its bad-input test (line,
column, message; nothing stored).
"""

from __future__ import annotations

import pytest
from motionsim.sim.errors import ParseError

from tests.sim.trio.conftest import fields, make, run_to


def mc4():
    return make(model="mc4xx")


def run(c, text: str, until: float = 0.5) -> dict:
    """Store ``text`` as program T, run it in process 1 and return its last process event."""
    c.store_program("T", text)
    c.run_program("T", 1)
    run_to(c, c.env.now + until)
    return fields(c, "process", process=1)[-1][1]


def refused(text: str) -> ParseError:
    """The compile error storing ``text`` gives; nothing is stored."""
    c = mc4()
    with pytest.raises(ParseError) as err:
        c.store_program("BAD", text)
    assert c.program_names() == []
    return err.value


# -- DIM x AS type = value -----------------------------------------------------------------------


def test_dim_with_an_initial_value_sets_it_as_its_type_stores_it():
    """§11.4: INTEGER truncates, BOOLEAN holds TRUE / FALSE, STRING keeps its length."""
    c = mc4()
    last = run(c, """\
DIM count AS INTEGER = 7.9
DIM ready AS BOOLEAN = 5
DIM rate AS FLOAT = 2.5 * 4
DIM msg AS STRING(4) = "ready"
DIM zero AS INTEGER = 0
VR(0) = count : VR(1) = ready : VR(2) = rate : VR(3) = LEN(msg) : VR(4) = zero
""")
    assert "error" not in last
    assert c.vr[:5] == [7.0, -1.0, 10.0, 4.0, 0.0]


def test_a_dim_runs_its_initial_value_again_each_time_the_line_runs():
    """A DIM inside a loop is declared again each pass: the value starts again [INF]."""
    c = mc4()
    run(c, """\
FOR k = 1 TO 3
  DIM total AS INTEGER = 10
  total = total + k
  VR(k) = total
NEXT k
""")
    assert c.vr[1:4] == [11.0, 12.0, 13.0]


@pytest.mark.parametrize(("text", "column", "message"), [
    ('DIM x AS INTEGER = "seven"\n', 1, "type mismatch"),
    ('DIM x AS STRING = 7\n', 1, "cannot assign a number to a string"),
    ("DIM a(3) AS FLOAT = 0\n", 21, "an array cannot take an initial value"),
    ("DIM x AS INTEGER =\n", 19, "expected a value"),
])
def test_a_bad_initial_value_is_a_compile_error_at_its_place(text, column, message):
    err = refused(text)
    assert (err.details["line"], err.details["column"]) == (1, column)
    assert message in err.message


# -- DIM a, b AS type ----------------------------------------------------------------------------


def test_several_names_on_one_dim_line_share_the_type_and_the_initial_value():
    c = mc4()
    last = run(c, """\
DIM ax, ay AS FLOAT
DIM i, j AS INTEGER = 3
DIM lo, hi(2) AS INTEGER
ax = 1.25 : ay = ax * 2 : i = i + 0.9
hi(1) = 4 : lo = 2.5
VR(0) = ax : VR(1) = ay : VR(2) = i : VR(3) = j : VR(4) = hi(1) + lo
""")
    assert "error" not in last
    assert c.vr[:5] == [1.25, 2.5, 3.0, 3.0, 6.0]


@pytest.mark.parametrize(("text", "column", "message"), [
    ("DIM a, AS FLOAT\n", 8, "AS is a Trio BASIC keyword"),
    ("DIM a, b FLOAT\n", 10, "expected 'AS'"),
    ("DIM i, i AS INTEGER\n", 8, "already declared (DIM twice)"),
    ("DIM a(2), b AS FLOAT(3)\n", 5, "the array size of A is given twice"),
])
def test_a_bad_dim_list_names_the_name_at_fault(text, column, message):
    err = refused(text)
    assert (err.details["line"], err.details["column"]) == (1, column)
    assert message in err.message


# -- two-dimensional arrays ----------------------------------------------------------------------


def test_a_two_dimensional_array_holds_an_element_per_index_pair():
    """``DIM s AS INTEGER(32, 3)`` (a station table of an MC4xx program) and the bracket
    form ``DIM t(2, 2) AS FLOAT``: indexes from 0, one element per pair."""
    c = mc4()
    last = run(c, """\
DIM station AS INTEGER(32, 3)
DIM t(2, 2) AS FLOAT
FOR n = 0 TO 31
  FOR f = 0 TO 2
    station(n, f) = n * 10 + f
  NEXT f
NEXT n
t(1, 0) = 0.5 : t(0, 1) = 2
VR(0) = station(31, 2) : VR(1) = station(0, 1) : VR(2) = station(12, 0)
VR(3) = t(1, 0) : VR(4) = t(0, 1) : VR(5) = t(1, 1)
""", until=2.0)
    assert "error" not in last
    assert c.vr[:6] == [312.0, 1.0, 120.0, 0.5, 2.0, 0.0]


@pytest.mark.parametrize(("index", "shown"), [("4, 0", "4, 0"), ("0, 3", "0, 3"),
                                              ("-1, 1", "-1, 1")])
def test_an_index_outside_either_dimension_stops_the_program_at_its_line(index, shown):
    c = mc4()
    last = run(c, f"DIM s AS INTEGER(4, 3)\nVR(0) = 1\nVR(1) = s({index})\nVR(2) = 1\n")
    assert last["state"] == "stopped" and last["line"] == 3
    assert f"Array index out of range: S({shown})" in last["error"]
    assert c.vr[:3] == [1.0, 0.0, 0.0]


@pytest.mark.parametrize(("text", "line", "column", "message"), [
    ("DIM s AS INTEGER(4, 3)\nVR(0) = s(1)\n", 2, 1, "S has 2 dimensions: it needs 2 indexes"),
    ("DIM s AS INTEGER(4)\ns(1, 2) = 0\n", 2, 1, "S has 1 dimension: it needs 1 index"),
    ("DIM s AS INTEGER(2, 3, 4)\n", 1, 17, "at most 2 dimensions, got 3"),
    ("DIM s(0, 3) AS FLOAT\n", 1, 7, "whole number >= 1"),
    ("DIM s AS FLOAT(1000, 1000)\n", 1, 5, "8000000 bytes"),
])
def test_a_bad_two_dimensional_array_is_a_compile_error(text, line, column, message):
    err = refused(text)
    assert (err.details["line"], err.details["column"]) == (line, column)
    assert message in err.message


# -- CONSTANT lines -----------------------------------------------------------------------------


def test_constant_lines_bare_name_and_expression_values():
    """``CONSTANT "name", value`` (§11.4) with a value worked out at compile time, and the
    bare-name form ``CONSTANT name, value`` [INF]: both name a read-only value."""
    c = mc4()
    last = run(c, """\
CONSTANT "two_pi", 2 * PI
CONSTANT max_speed, 1500
CONSTANT "mask", $FF AND NOT 1
CONSTANT "neg", -(3 + 4)
VR(0) = two_pi : VR(1) = max_speed : VR(2) = mask : VR(3) = neg
""")
    assert "error" not in last
    assert c.vr[:4] == [pytest.approx(6.283185307179586), 1500.0, 254.0, -7.0]
    assert c.terminal("? max_speed").reply == "1500.0000"  # visible to the command line


@pytest.mark.parametrize(("text", "column", "message"), [
    ('CONSTANT "x", VR(3)\n', 15, "CONSTANT needs a number known when the program is compiled"),
    ("CONSTANT max_speed 1500\n", 20, "expected ','"),
    ("CONSTANT SPEED, 10\n", 10, "SPEED is a Trio BASIC keyword"),
    ('CONSTANT "x", 1 / 0\n', 15, "CONSTANT needs a number"),
])
def test_a_bad_constant_line_is_a_compile_error(text, column, message):
    err = refused(text)
    assert (err.details["line"], err.details["column"]) == (1, column)
    assert message in err.message


def test_writing_a_constant_is_a_compile_error_at_the_assignment():
    err = refused("CONSTANT max_speed, 1500\nmax_speed = 3\n")
    assert (err.details["line"], err.details["column"]) == (2, 1)
    assert "MAX_SPEED is a CONSTANT" in err.message


# -- significant characters (TJ1P-26) ------------------------------------------------------------


def test_two_variables_agreeing_in_their_first_16_characters_are_one_variable():
    """TJ1P-26: the first 16 characters of a local variable's name are significant."""
    c = make()  # every model [INF]
    last = run(c, """\
conveyor_speed_a_left = 5
VR(0) = conveyor_speed_a_right
conveyor_speed_b = 7
VR(1) = conveyor_speed_c
""")
    assert "error" not in last
    assert c.vr[:2] == [5.0, 0.0]  # 16 alike: one name; 15 alike then different: two


def test_a_long_label_is_known_by_its_first_15_characters():
    c = make()
    last = run(c, """\
GOSUB home_all_axes_first
VR(1) = 2
STOP
home_all_axes_fX:
  VR(0) = 1
  RETURN
""")
    assert "error" not in last
    assert c.vr[:2] == [1.0, 2.0]


def test_two_labels_agreeing_in_their_first_15_characters_are_one_label_defined_twice():
    c = mc4()
    with pytest.raises(ParseError) as err:
        c.store_program("BAD", "GOTO start_motion_x\nstart_motion_axis_1:\nstart_motion_axis_2:\n")
    d = err.value.details
    assert (d["line"], d["column"]) == (3, 1)
    assert "only the first 15 characters of a label are significant" in err.value.message


def test_two_dims_agreeing_in_their_first_16_characters_are_one_name_declared_twice():
    err = refused("DIM axis_position_x1a AS FLOAT\nDIM axis_position_x1b AS FLOAT\n")
    assert (err.details["line"], err.details["column"]) == (2, 1)
    assert "only the first 16 characters of a name are significant" in err.message


def test_keywords_longer_than_16_characters_are_matched_in_full():
    """Cutting applies to a program's own names only: a keyword is read whole."""
    c = mc4()
    last = run(c, "DIM a_very_long_local_name AS INTEGER = 3\nVR(0) = a_very_long_local_name\n")
    assert "error" not in last and c.vr[0] == 3.0
