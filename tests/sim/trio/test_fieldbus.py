"""System and fieldbus functions with several arguments (issue 32 item 3): ETHERCAT, ETHERNET,
PEEK, PROFINET, MODBUS, ETHERNETIP, CO_READ, CO_WRITE as statements and as values.

Sources: spec trio.md §11.7 (real start-up code: ``ETHERCAT(0,0)``, ``ETHERCAT($22,0,vr)``
with 3 = operational); Trio host code read for the forms (``ETHERCAT($22,0,-1)`` read back as
an integer, ``ETHERCAT(3,0,vr)`` the slave count, ``ETHERCAT($21,0,state,0)``, ``ETHERCAT(1,0)``
stop; states 0 Init .. 3 Operational); M216-547 (ETHERNET read). What is not simulated says so
by name at run time (sim/trio/card/fieldbus.py).
"""

from __future__ import annotations

import pytest
from motionsim.sim.errors import InvalidValue, ParseError

from tests.sim.trio.conftest import fields, make, run_to


def mc4(**config):
    return make(model="mc4xx", **config)


def run(c, text: str, until: float = 0.5) -> dict:
    c.store_program("T", text)
    c.run_program("T", 1)
    run_to(c, c.env.now + until)
    return fields(c, "process", process=1)[-1][1]


def setups(c) -> list[tuple[int, str, list]]:
    return [(round(t * 1e6), f["command"], f["args"]) for t, f in fields(c, "setup")]


STARTUP = """\
' bring the EtherCAT network up and wait for it, as an MC4xx start-up program does
CONSTANT "ecat_state", 59
CONSTANT "ecat_slaves", 60
ETHERCAT(0, 0)
REPEAT
  ETHERCAT($22, 0, ecat_state)
  IF VR(ecat_state) <> 3 THEN WA(100)
UNTIL VR(ecat_state) = 3
ETHERCAT(3, 0, ecat_slaves)
IF VR(ecat_slaves) <> 4 THEN
  PRINT "wrong number of drives"
  STOP
ENDIF
VR(61) = 1
"""


def test_a_start_up_program_polling_the_network_finds_it_operational_with_its_slaves():
    c = mc4(axes=4)
    last = run(c, STARTUP)
    assert "error" not in last
    assert c.vr[59:62] == [3.0, 4.0, 1.0]
    # 100 µs a statement; REPEAT itself runs nothing (the loop's start)
    assert setups(c) == [(200, "ETHERCAT", [0.0, 0.0]), (300, "ETHERCAT", [34.0, 0.0, 59.0]),
                         (600, "ETHERCAT", [3.0, 0.0, 60.0])]


def test_the_slave_count_is_the_config_ethercat_slaves_one_per_axis_by_default():
    assert make(axes=3).terminal("ETHERCAT(3, 0)").reply == "3"
    assert mc4(ethercat_slaves=7).terminal("ETHERCAT(3,0,-1)").reply == "7"
    with pytest.raises(InvalidValue, match="ethercat_slaves"):
        mc4(ethercat_slaves=-2)


def test_stop_and_state_requests_change_what_the_state_reads():
    c = mc4()
    last = run(c, """\
ETHERCAT(1, 0)
ETHERCAT($22, 0, 10)
ETHERCAT($21, 0, 2, 0)
ETHERCAT($22, 0, 11)
ETHERCAT(0, 0)
ETHERCAT($22, 0, 12)
""")
    assert "error" not in last
    assert c.vr[10:13] == [0.0, 2.0, 3.0]


def test_etherCAT_and_ethernet_as_values():
    """Used as a value a read answers what it read, a command TRUE (-1) [BK]; -1 as the VR
    argument prints the result as a whole number, as a host reads it."""
    c = mc4()
    last = run(c, """\
IF ETHERCAT($22, 0) = 3 THEN VR(0) = ETHERCAT(3, 0) + 100
VR(1) = ETHERCAT(0, 0)
VR(2) = ETHERNET(0, -1, 10)
VR(3) = ETHERCAT($22, 0, -1)
""")
    assert "error" not in last
    assert c.vr[:4] == [108.0, -1.0, 502.0, 3.0]
    assert c.unread_output("t") == ["3"]  # only the -1 form printed
    assert c.terminal("ETHERCAT($22,0,-1)").reply == "3"
    assert c.terminal("? ETHERCAT($22, 0) * 2").reply == "6.0000"


def test_an_ethercat_function_not_modelled_is_a_run_time_error_naming_it():
    c = mc4()
    last = run(c, "ETHERCAT(0, 0)\nETHERCAT($87, 0)\nVR(0) = 1\n")
    assert last["state"] == "stopped" and last["line"] == 2
    assert "ETHERCAT function $87 is not simulated" in last["error"]
    assert c.vr[0] == 0.0


def test_a_drive_fault_reset_succeeds_there_being_no_drive_fault():
    """``ETHERCAT($64, axis, 1, 50)`` in a real error handler [BK]: TRUE, nothing changes;
    an axis that does not exist is still an error."""
    c = mc4(axes=2)
    last = run(c, "VR(0) = ETHERCAT($64, 1, 1, 50)\nETHERCAT($64, 7, 1, 50)\n")
    assert c.vr[0] == -1.0
    assert last["line"] == 2 and "Axis number out of range: 7" in last["error"]


# -- the buses not simulated --------------------------------------------------------------------


UNSIMULATED = [
    ("PEEK", "VR(0) = PEEK($2000)"),
    ("PEEK", "VR(0) = PEEK($2000, $FF)"),
    ("PROFINET", "PROFINET(2, 0, 1, 10, 100, 0)"),
    ("PROFINET", "IF PROFINET(5, 0, 90) THEN VR(0) = 1"),
    ("MODBUS", "MODBUS(0, 1, 192, 168, 0, 10, 502)"),
    ("MODBUS", "MODBUS(4, 1, 100)"),
    ("ETHERNETIP", "ETHERNETIP(0)"),
    ("ETHERNETIP", "ok = ETHERNETIP(2, 0, 100, 8)"),
    ("CO_READ", "CO_READ(0, 1, $1000, 0, 5, 100)"),
    ("CO_WRITE", "result = CO_WRITE(0, 1, $6040, 0, 6, 15)"),
]


@pytest.mark.parametrize(("name", "line"), UNSIMULATED)
def test_every_argument_form_parses_and_running_it_says_not_simulated_by_name(name, line):
    c = mc4()
    last = run(c, f"VR(5) = 1\n{line}\nVR(6) = 1\n")
    assert last["state"] == "stopped" and last["line"] == 2
    assert f"{name} is not simulated" in last["error"]
    assert c.vr[5:7] == [1.0, 0.0]


def test_a_not_simulated_bus_is_a_basic_error_an_error_handler_takes():
    c = mc4()
    last = run(c, """\
ON BASICERROR GOTO no_bus
PROFINET(2, 0, 1, 10, 100, 0)
STOP
no_bus:
  VR(0) = ERROR_LINE
""")
    assert "error" not in last and c.vr[0] == 2.0
    (_t, f), = fields(c, "basic_error")
    assert "PROFINET is not simulated" in f["error"] and f["line"] == 2


@pytest.mark.parametrize(("text", "column", "message"), [
    ("ETHERCAT\n", 9, "ETHERCAT needs its arguments in brackets"),
    ("ETHERCAT(0)\n", 9, "ETHERCAT takes 2 to 16 arguments, got 1"),
    ("VR(0) = PEEK(1, 2, 3)\n", 13, "PEEK takes 1 to 2 arguments, got 3"),
    ("x = MODBUS\n", 11, "MODBUS needs its arguments in brackets"),
    ("ethercat = 3\n", 1, "ETHERCAT is a Trio BASIC keyword"),
    ('CO_READ("a")\n', 1, "a number is needed here"),
])
def test_a_bad_bus_call_is_a_compile_error_at_its_column(text, column, message):
    c = mc4()
    with pytest.raises(ParseError) as err:
        c.store_program("BAD", text)
    assert (err.value.details["line"], err.value.details["column"]) == (1, column)
    assert message in err.value.message
    assert c.program_names() == []


def test_the_bus_functions_run_on_the_earlier_models_too():
    c = make(model="mc2xx", axes=2)
    last = run(c, "ETHERCAT($22, 0, 3)\nVR(4) = ETHERCAT(3, 0)\n")
    assert "error" not in last and c.vr[3:5] == [3.0, 2.0]
