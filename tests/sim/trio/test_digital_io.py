"""Digital I/O: OP(n, state), OP(pattern), READ_OP(n), IN(n), IN(a, b), AIN(n) and the
``output`` events (TRM chapter 8 "Input / Output Commands"; spec trio.md §2.3; pattern and
IN(a, b) layout ``[BK]``, sim/trio/io.py)."""

from __future__ import annotations

import pytest

from tests.sim.trio.conftest import fields, make, run_to


def outputs(c) -> list[tuple[float, int, int]]:
    return [(t, f["output"], f["value"]) for t, f in fields(c, "output")]


def test_op_switches_one_output_and_logs_each_change_at_its_instant():
    c = make()
    c.store_program("IO", "OP(8,ON)\nOP(8,ON)\nOP(9,1)\nOP(8,OFF)\n")
    c.run_program("IO", 1)
    run_to(c, 0.01)
    # one statement per 100 µs; the repeated OP(8,ON) changes nothing and logs nothing
    assert outputs(c) == [(0.0, 8, 1), (pytest.approx(0.0002), 9, 1),
                          (pytest.approx(0.0003), 8, 0)]
    assert c.terminal("? READ_OP(8), READ_OP(9), OP(9)").reply == "0.0000\t1.0000\t1.0000"


def test_op_with_one_argument_writes_outputs_from_8_as_a_bit_pattern():
    c = make()
    c.terminal("OP(5)")  # binary 101: outputs 8 and 10
    assert [(o, v) for _t, o, v in outputs(c)] == [(8, 1), (10, 1)]
    c.terminal("OP($1FFFF)")  # 16 outputs: bit 16 (output 24) is not one of them
    assert c.terminal("? READ_OP(23), READ_OP(24), READ_OP(7)").reply == (
        "1.0000\t0.0000\t0.0000")
    c.terminal("OP(0)")
    assert all(c.get_variable(f"OP({n})") == 0.0 for n in range(8, 24))


def test_inputs_read_off_until_set_from_outside():
    c = make()
    assert c.terminal("? IN(0), IN(7)").reply == "0.0000\t0.0000"
    c.set_variable("IN(3)", 1)
    c.set_variable("IN(5)", 24.0)  # any non-zero value drives the input ON
    assert c.get_variable("IN(5)") == 1.0
    assert c.terminal("? IN(3), IN(4)").reply == "1.0000\t0.0000"
    assert c.terminal("? IN(3,5)").reply == "5.0000"  # input 3 is bit 0
    assert c.terminal("? IN(3,4)").reply == "1.0000"  # input 5 is past the range
    assert c.terminal("? IN").reply == f"{(1 << 3) + (1 << 5):.4f}"
    assert fields(c, "output") == []  # inputs are not outputs


def test_program_waits_for_an_input_then_switches_an_output():
    c = make()
    c.store_program("WAITIN", "WAIT UNTIL IN(2)=ON\nOP(12,ON)\n")
    c.run_program("WAITIN", 1)
    run_to(c, 0.0105)
    assert outputs(c) == []
    c.set_variable("IN(2)", 1)
    run_to(c, 0.1)
    # WAIT UNTIL is re-tested once per servo period: the next one is 11 ms
    assert outputs(c) == [(pytest.approx(0.0111), 12, 1)]


def test_an_input_set_off_again_reads_off():
    c = make()
    c.set_variable("IN(4)", 1)
    c.set_variable("IN(4)", 0)
    assert c.get_variable("IN(4)") == 0.0
    assert c.terminal("? IN(4), IN(0,7)").reply == "0.0000\t0.0000"


def test_the_last_channel_255_is_an_output_and_an_input():
    c = make()
    assert c.terminal("OP(255,ON)").error is None
    c.set_variable("IN(255)", 1)
    assert c.terminal("? READ_OP(255), IN(255)").reply == "1.0000\t1.0000"
    assert [(f["output"], f["value"]) for _t, f in fields(c, "output")] == [(255, 1)]


def test_ain_reads_zero():
    c = make()
    assert c.terminal("? AIN(0)").reply == "0.0000"


def test_output_written_over_rest_is_an_output_change():
    c = make()
    c.set_variable("OP(15)", 1)
    assert c.terminal("? READ_OP(15)").reply == "1.0000"
    assert [(o, v) for _t, o, v in outputs(c)] == [(15, 1)]


@pytest.mark.parametrize("cmd", ["OP(256,ON)", "OP(-1,ON)", "? IN(300)", "? AIN(999)",
                                 "? READ_OP(256)"])
def test_io_number_out_of_range_is_an_error_that_changes_nothing(cmd):
    c = make()
    r = c.terminal(cmd)
    assert r.error is not None and "Parameter out of range" in r.error
    assert fields(c, "output") == []


@pytest.mark.parametrize(("text", "column"), [("OP(1,2,3)", 3), ("VR(1)=READ_OP", 14),
                                                ("VR(1)=IN(1,2,3)", 9)])
def test_io_call_with_wrong_arguments_is_refused_at_load_with_its_column(text, column):
    from motionsim.sim.errors import ParseError

    c = make()
    with pytest.raises(ParseError) as exc:
        c.store_program("BADIO", text)
    assert exc.value.details["line"] == 1 and exc.value.details["column"] == column
    assert c.program_names() == []


def test_rest_variable_names_cover_in_and_op_ranges():
    from motionsim.sim.errors import NotFound

    c = make()
    with pytest.raises(NotFound):
        c.get_variable("IN(256)")
    with pytest.raises(NotFound):
        c.set_variable("OP(999)", 1)
    assert fields(c, "output") == []
