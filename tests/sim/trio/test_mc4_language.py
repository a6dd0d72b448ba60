"""The MC4xx / MC6xx language additions real programs use (spec trio.md §11.2, §11.4, §11.8,
§11.10): INCLUDE, DIM with types and arrays, GLOBAL / CONSTANT, string variables and functions,
bit access, PRINT("..."), TICKS — and that an earlier model answers its own syntax error."""

from __future__ import annotations

import pytest
from motionsim.sim.errors import ParseError

from tests.sim.trio.conftest import fields, make, run_to

INITIALISE = """\
' named inputs and VR indices of the machine, never RUN on its own
estop_in = 7
count_vr = 20
DIM limit AS INTEGER
"""


def mc4():
    return make(model="mc4xx")


def ran(c, program: str, process: int = 1, until: float = 0.5) -> dict:
    """Run a stored program and return its last ``process`` event's fields."""
    c.run_program(program, process)
    run_to(c, c.env.now + until)
    return fields(c, "process", process=process)[-1][1]


# -- INCLUDE (§11.2) ---------------------------------------------------------------------------


def test_p11_2_include_makes_the_included_names_locals_of_each_including_program():
    c = mc4()
    c.store_program("INITIALISE", INITIALISE)
    c.store_program("MAIN", 'INCLUDE "INITIALISE"\nVR(count_vr) = estop_in\nlimit = 2.9\n'
                            "VR(21) = limit\n")
    c.store_program("OTHER", 'INCLUDE "INITIALISE"\nVR(count_vr + 2) = estop_in * 2\n')
    assert "error" not in ran(c, "MAIN", 1)
    assert "error" not in ran(c, "OTHER", 2)
    assert (c.vr[20], c.vr[21], c.vr[22]) == (7.0, 2.0, 14.0)  # limit: INTEGER from INITIALISE


def test_p11_2_include_is_resolved_at_compile_time_and_costs_no_run_time():
    plain, included = mc4(), mc4()
    plain.store_program("P", "OP(8, ON)\nOP(9, ON)\n")
    included.store_program("INITIALISE", INITIALISE)
    included.store_program("P", 'INCLUDE "INITIALISE"\nOP(8, ON)\nOP(9, ON)\n')
    for c in (plain, included):
        ran(c, "P")
    times = [[t for t, _f in fields(c, "output")] for c in (plain, included)]
    assert times[0] == times[1] == pytest.approx([0.0, 100e-6])  # 100 µs per statement


def test_p11_2_storing_the_included_program_again_recompiles_the_programs_that_include_it():
    c = mc4()
    c.store_program("INITIALISE", INITIALISE)
    c.store_program("MAIN", 'INCLUDE "INITIALISE"\nVR(count_vr) = estop_in\n')
    c.store_program("INITIALISE", INITIALISE.replace("estop_in = 7", "estop_in = 11"))
    ran(c, "MAIN")
    assert c.vr[20] == 11.0


def test_p11_2_a_new_included_program_that_breaks_an_includer_is_refused_and_changes_nothing():
    c = mc4()
    c.store_program("INITIALISE", INITIALISE)
    c.store_program("MAIN", 'INCLUDE "INITIALISE"\nVR(count_vr) = estop_in\n')
    with pytest.raises(ParseError) as err:
        c.store_program("INITIALISE", "DIM estop_in AS STRING\nestop_in = \"seven\"\n")
    d = err.value.details
    assert d["program"] == "MAIN" and d["line"] == 2  # MAIN's VR(count_vr) = a string
    assert c.program("INITIALISE") == INITIALISE
    ran(c, "MAIN")
    assert c.vr[20] == 7.0


# -- DIM and typed locals (§11.4) ------------------------------------------------------------


def test_p11_4_dim_types_integer_truncates_boolean_is_true_or_false_string_keeps_its_length():
    c = mc4()
    c.store_program("T", """\
DIM i AS INTEGER
DIM f AS FLOAT
DIM b AS BOOLEAN
DIM s AS STRING(5)
i = -3.7 : f = 2.5 : b = 5
s = "ABCDEFG"
VR(0) = i : VR(1) = f : VR(2) = b : VR(3) = LEN(s)
PRINT s
""")
    assert "error" not in ran(c, "T")
    assert c.vr[:4] == [-3.0, 2.5, -1.0, 5.0]
    assert c.unread_output("t")[-1] == "ABCDE"


def test_p11_4_dim_arrays_are_indexed_from_0_and_out_of_range_is_a_run_time_error():
    c = mc4()
    c.store_program("A", """\
DIM pos(4) AS FLOAT
FOR k = 0 TO 3
  pos(k) = k * 10
NEXT k
VR(0) = pos(0) + pos(3)
VR(1) = pos(4)
""")
    last = ran(c, "A")
    assert c.vr[0] == 30.0
    assert last["state"] == "stopped" and last["line"] == 6
    assert "Array index out of range: POS(4)" in last["error"]


# -- GLOBAL / CONSTANT (§11.4) -------------------------------------------------------------------


def test_p11_4_global_and_constant_name_a_vr_and_a_value_for_every_program_once_run():
    c = mc4()
    c.store_program("STARTUP", 'GLOBAL "batch_count", 50\nCONSTANT "batch_size", 12\n'
                               "batch_count = batch_size / 2\n")
    c.store_program("USER", "batch_count = batch_count + batch_size\n")  # before STARTUP ran
    ran(c, "STARTUP")
    assert c.vr[50] == 6.0
    ran(c, "USER", 2)  # compiled again at RUN: the names now stand for VR(50) and 12
    assert c.vr[50] == 18.0
    assert c.terminal("? batch_count").reply == "18.0000"
    assert c.terminal("? batch_size").reply == "12.0000"


# -- strings (§11.4) ----------------------------------------------------------------------------


def test_p11_4_string_variables_and_the_string_functions():
    c = mc4()
    c.store_program("S", """\
DIM name AS STRING(20)
DIM part AS STRING
name = "axis" + "_" + STR(3, 0)
PRINT name; " "; UCASE(LEFT(name, 4)); " "; RIGHT(name, 1); " "; MID(name, 2, 3)
VR(0) = LEN(name) : VR(1) = INSTR(name, "_") : VR(2) = VAL("12.5mm")
part = CHR(65) + CHR(66)
IF part = "AB" AND name <> "" THEN VR(3) = 1
""")
    assert "error" not in ran(c, "S")
    assert c.unread_output("t") == ["axis_3 AXIS 3 xis"]
    assert c.vr[:4] == [6.0, 5.0, 12.5, 1.0]


# -- bit access and PRINT( ) (§11.8) ------------------------------------------------------------


def test_p11_8_bit_access_reads_and_writes_bits_of_a_variable_a_vr_and_a_parameter():
    c = mc4()
    c.store_program("B", """\
s_mode = 5
options = 0
options.4 = ON
options.10 = s_mode.0
VR(5) = 12
VR(5).0 = ON
VR(5).2 = OFF
VR(0) = options : VR(1) = VR(5) : VR(2) = VR(5).3 : VR(3) = (s_mode + 2).1
VR(4) = AXISSTATUS AXIS(0).4
""")
    assert "error" not in ran(c, "B")
    assert c.vr[:5] == [16.0 + 1024.0, 9.0, 1.0, 1.0, 0.0]


def test_p11_8_print_with_brackets_around_a_string_on_every_model():
    for model in ("mc2xx", "mc4xx"):
        c = make(model=model)
        c.store_program("P", 'PRINT("ready")\nPRINT ("x = "); 2\n')
        ran(c, "P")
        assert c.unread_output("t") == ["ready", "x = 2.0000"]


# -- TICKS (§11.10) -----------------------------------------------------------------------------


def test_p11_10_ticks_counts_down_by_one_every_servo_period_per_process():
    c = mc4()
    c.store_program("T", "TICKS = 50\nWAIT UNTIL TICKS <= 0\nOP(8, ON)\n")
    c.run_program("T", 1)
    run_to(c, 0.0205)
    assert c.terminal("? TICKS PROC(1)").reply == "30.0000"
    assert c.terminal("? TICKS PROC(2)").reply == "0.0000"  # each process its own
    run_to(c, 0.2)
    (t, f), = fields(c, "output")
    assert f["output"] == 8 and t == pytest.approx(0.050 + 100e-6)  # 50 periods after line 1


# -- a later generation's keywords on an earlier model ------------------------------------------


@pytest.mark.parametrize("model", ["series2", "mc2xx"])
@pytest.mark.parametrize(("text", "column", "word"), [
    ('INCLUDE "INITIALISE"\n', 1, "INCLUDE"),
    ("DIM i AS INTEGER\n", 1, "DIM"),
    ('GLOBAL "x", 10\n', 1, "GLOBAL"),
    ('CONSTANT "x", 10\n', 1, "CONSTANT"),
    ("x = 1\nVR(0) = LEN(x)\n", 9, "LEN"),
    ("x = VR(5).2\n", 10, "bit access"),
])
def test_mc4_keyword_on_an_earlier_model_is_that_models_syntax_error(model, text, column, word):
    c = make(model=model)
    with pytest.raises(ParseError) as err:
        c.store_program("P", text)
    d = err.value.details
    assert d["column"] == column and d["program"] == "P"
    assert word in err.value.message and "MC4xx" in err.value.message and model in \
        err.value.message
    assert c.program_names() == []


def test_mc4_words_stay_ordinary_names_on_an_earlier_model_but_are_keywords_on_mc4xx():
    old = make(model="mc2xx")
    old.store_program("P", "dim = 3\nVR(0) = dim\n")
    ran(old, "P")
    assert old.vr[0] == 3.0
    with pytest.raises(ParseError) as err:
        mc4().store_program("P", "dim = 3\n")
    assert "keyword" in err.value.message


def test_p11_8_bracketed_program_names_of_run_and_stop():
    c = mc4()
    c.store_program("WORKER", "WHILE TRUE\n  VR(1) = VR(1) + 1\nWEND\n")
    c.store_program("BOSS", 'RUN("WORKER", 3)\nWA(10)\nSTOP("WORKER")\n'
                            "VR(2) = PROC_STATUS PROC(3)\n")
    ran(c, "BOSS", 1)
    starts = [f["process"] for _t, f in fields(c, "process", state="running")]
    assert starts[:2] == [1, 3]
    (t, _f), = fields(c, "process", process=3, state="stopped")
    assert t == pytest.approx(0.010 + 200e-6) and c.vr[2] == 0.0


def test_p11_4_global_and_constant_typed_at_the_command_line_name_things_for_programs():
    c = mc4()
    assert c.terminal('GLOBAL "part_count", 40').error is None
    assert c.terminal('CONSTANT "part_max", 3').error is None
    assert c.terminal("part_count = part_max * 2").error is None
    assert c.vr[40] == 6.0
    c.store_program("P", "part_count = part_count + part_max\n")
    ran(c, "P")
    assert c.terminal("? part_count").reply == "9.0000"
