"""A program using a Trio BASIC command the simulator does not model is refused when stored,
with the line, the column and "not simulated" — a code of its own (HTTP 501), not a syntax
error — and
nothing changes. An empty program text is refused too. The keyword list is the TRM chapter-8
command index (docslib contents pages, :mod:`motionsim.sim.trio.keywords`)."""

from __future__ import annotations

import pytest
from motionsim.sim.errors import InvalidValue, NotSimulated, ParseError
from motionsim.sim.trio.language.keywords import INDEX, NOT_SIMULATED, SIMULATED, index_rows


@pytest.mark.parametrize(
    ("text", "line", "column", "keyword"),
    [
        ("MOVE(10)\nBACKLASH(1,2,3)\n", 2, 1, "BACKLASH"),
        ("IF LOOKUP<0 THEN\n MOVE(1)\nENDIF\n", 1, 4, "LOOKUP"),
        ("x=1\n  PSWITCH(1,ON)\n", 2, 3, "PSWITCH"),
        ("x=1\nKEY\n", 2, 1, "KEY"),
        ("REGIST(3) AXIS(1)\n", 1, 1, "REGIST"),
    ],
)
def test_not_simulated_command_refused_at_load_with_line_and_column(trio, text, line, column,
                                                                    keyword):
    trio.store_program("OLD", "VR(1)=1\n")
    with pytest.raises(NotSimulated) as err:
        trio.store_program("OLD", text)
    e = err.value
    d = e.details
    assert (e.code, d["line"], d["column"], d["keyword"]) == ("not_simulated", line, column,
                                                             keyword)
    assert not isinstance(e, ParseError)  # not a syntax error
    assert "not simulated" in e.message
    assert trio.program("OLD") == "VR(1)=1\n"  # nothing changed
    assert trio.log.last_seq == 0


def test_syntax_error_is_still_a_parse_error(trio):
    with pytest.raises(ParseError) as err:
        trio.store_program("P", "MOVE(10\n")
    assert err.value.code == "parse_error"


def test_not_simulated_at_the_command_line_is_an_error_reply(trio):
    r = trio.terminal("BACKLASH(1,2,3) AXIS(0)")
    assert r.done and "not simulated" in r.error and "column 1" in r.error
    assert r.detail is not None and r.detail[0] == "not_simulated"


@pytest.mark.parametrize("text", ["", "\n\n", "   \r\n"])
def test_empty_program_refused_not_stored(trio, text):
    with pytest.raises(InvalidValue) as err:
        trio.store_program("EMPTY", text)
    assert err.value.details["field"] == "body"
    assert trio.program_names() == []


def test_index_split_into_simulated_and_not():
    rows = index_rows()
    assert len(rows) == sum(len(v) for v in INDEX.values())
    assert {"MOVEMODIFY", "CONNECT", "CAM", "CAMBOX", "DEFPOS", "PRINT#", "HEX", "OP", "IN",
            "READ_OP", "AIN"} <= SIMULATED
    assert {"BACKLASH", "REGIST", "PSWITCH", "LOOKUP"} <= NOT_SIMULATED
    assert not SIMULATED & NOT_SIMULATED


def test_no_word_is_both_simulated_by_the_motion_modules_and_refused():
    """The refused list names only what no module models: a set-up command or stored
    parameter that :mod:`~motionsim.sim.trio.parameters` simulates is not in it."""
    from motionsim.sim.trio.language.keywords import MOTION_WORDS

    assert not NOT_SIMULATED & MOTION_WORDS
