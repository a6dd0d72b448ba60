"""Program output: PRINT on channel 0 (the command line), PRINT #n, OUTDEVICE, the run-time
error line, HEX() and number formats per model.

Sources: OUTDEVICE TRM p. 8-130 (MC206 listing p. 320); channel 0 = the terminal (TN20);
PRINT #n M206-475; four decimals `255.0000` (TJ1P-27, M224-291); HEX(-10) -> FFFFF6 on the
32-bit word (TJ1P-27) and 53-bit on the 64-bit word (TJ2P-19); models: spec §10.9.
"""

from __future__ import annotations

import pytest
from motionsim.sim.errors import InvalidValue

from tests.sim.trio.conftest import fields, make, run_to


def _run(c, text: str, process: int = 1) -> None:
    c.store_program("OUT", text)
    c.run_program("OUT", process)


def test_print_from_a_program_reaches_channel_0(trio):
    _run(trio, 'PRINT "part ";3\nPRINT 255\n')
    run_to(trio, 0.01)
    assert [f for _, f in fields(trio, "print")] == [
        {"process": 1, "channel": 0, "text": "part 3.0000"},
        {"process": 1, "channel": 0, "text": "255.0000"},
    ]
    assert trio.unread_output("rest") == ["part 3.0000", "255.0000"]
    assert trio.unread_output("rest") == []  # each reader sees a line once


def test_print_hash_n_and_outdevice_choose_the_channel(trio):
    _run(trio, 'PRINT #5, "status"\nOUTDEVICE=7\nPRINT "err"\nVR(1)=OUTDEVICE\n'
               'OUTDEVICE=0\nPRINT "back"\n')
    run_to(trio, 0.01)
    assert [(f["channel"], f["text"]) for _, f in fields(trio, "print")] == [
        (5, "status"), (7, "err"), (0, "back")
    ]
    assert trio.unread_output("rest") == ["back"]  # only channel 0 is the command line
    assert trio.get_variable("VR(1)") == 7.0


def test_run_time_error_line_is_printed_on_channel_0_and_stops_only_its_process(trio):
    trio.store_program("GOOD", "FOR i=1 TO 100\n VR(10)=i\nNEXT i\n")
    trio.run_program("GOOD", 2)
    _run(trio, "VR(1)=1\nVR(2)=1/0\n", process=3)
    run_to(trio, 0.1)
    assert trio.unread_output("rest") == ["%[Process 3:Line 2] - Divide by zero"]
    assert trio.get_variable("VR(10)") == 100.0


def test_bad_channel_is_a_run_time_error(trio):
    _run(trio, 'PRINT #12, "x"\n')
    run_to(trio, 0.01)
    assert trio.processes()[0]["error"].endswith("Channel number out of range: 12")


@pytest.mark.parametrize(
    ("model", "value", "text"),
    [("mc2xx", -10, "FFFFF6"), ("series2", -10, "FFFFF6"), ("mc2xx", 65536, "10000"),
     ("mc4xx", -10, "1FFFFFFFFFFFF6"), ("mc4xx", 255, "FF")],
)
def test_hex_prints_the_word_in_twos_complement(model, value, text):
    c = make(model=model)
    assert c.terminal(f"PRINT HEX({value})").reply == text


def test_hex_two_items_separated_by_a_comma(trio):
    assert trio.terminal("PRINT HEX(-10),HEX(65536)").reply == "FFFFF6\t10000"


@pytest.mark.parametrize(("model", "text"), [("mc2xx", "0.3333333433"), ("mc4xx", "0.3333333333")])
def test_print_precision_follows_the_model_word(model, text):
    """32-bit models hold single precision (TJ1P-27), 64-bit ones double (TJ2P-19)."""
    c = make(model=model)
    assert c.terminal("PRINT 1/3[10]").reply == text
    assert c.terminal("PRINT 16777217[0]").reply == ("16777216" if model == "mc2xx"
                                                    else "16777217")


def test_default_model_is_mc2xx_with_seven_processes(trio):
    assert trio.model.name == "mc2xx" and trio.n_processes == 7
    assert make(model="mc4xx").n_processes == 22
    assert make(model="series2", processes=3).n_processes == 3


def test_unknown_model_is_refused_naming_the_known_ones():
    with pytest.raises(InvalidValue) as err:
        make(model="mc999")
    assert err.value.details["field"] == "model" and "mc4xx" in err.value.message


def test_print_at_the_command_line_is_the_reply_and_hash_n_goes_elsewhere(trio):
    r = trio.terminal('PRINT #6, "to mp" : ? 2')
    assert r.reply == "2.0000"
    assert [(f["process"], f["channel"], f["text"]) for _, f in fields(trio, "print")] == [
        (0, 6, "to mp")
    ]
