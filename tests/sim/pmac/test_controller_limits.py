"""The Turbo PMAC's number ranges and memory limits at the controller's edges: I-variables
I0..I8191 (TSRM p23), programs B0..B32767 (TSRM OPEN PROG: 1-32767), motors #1..#32, the
65 536 words of buffer memory a rotary or gather buffer may take whole (TSRM DEFINE ROT /
DEFINE GATHER, ERR006 when short), and variable writes that must be finite numbers."""

from __future__ import annotations

import math

import pytest
from motionsim.sim.errors import InvalidValue, NotFound
from motionsim.sim.pmac import PmacController


def test_config_i_variables_run_from_i0_to_i8191():
    """TSRM p23: I0..I8191. A config key naming I8191 sets it; I8192 is refused, naming the
    key."""
    assert PmacController("pmac", {"i8191": 7}).get_variable("I8191") == 7.0
    with pytest.raises(InvalidValue) as refused:
        PmacController("pmac", {"i8192": 7})
    assert refused.value.details["field"] == "i8192"


@pytest.mark.parametrize(("command", "error"), [
    ("&1 B32767", None), ("&1 B0", None), ("&1 B32768", "ERR003"), ("&1 B-1", "ERR003"),
])
def test_b_points_at_programs_0_to_32767(rig, command, error):
    """``B0`` is the rotary buffer, ``B{n}`` PROG n, n at most 32767 (TSRM OPEN PROG)."""
    assert rig.cmd(command).error == error


def test_a_rotary_buffer_may_take_all_free_memory_and_not_one_word_more(rig):
    """``DEFINE ROT`` takes words of the 65 536 free on an empty card: all of them fit (SIZE
    then 0), one more is ERR006 and defines nothing."""
    assert rig.ok("SIZE") == "65536"
    too_big = rig.cmd("&1 DEFINE ROT 65537")
    assert too_big.error == "ERR006"
    assert rig.c.rotary(1) is None
    rig.ok("&1 DEFINE ROT 65536")
    assert rig.ok("SIZE") == "0"
    assert rig.c.rotary(1)["size_words"] == 65536


def test_define_gather_takes_what_it_is_given_or_all_free_memory(rig):
    """``DEFINE GATHER n`` of exactly the free memory fits, one word more is ERR006; with no
    size it takes all that is free."""
    rig.ok("&1 DEFINE ROT 1000")
    free = int(rig.ok("SIZE"))
    assert rig.cmd(f"DEFINE GATHER {free + 1}").error == "ERR006"
    assert rig.ok("SIZE") == str(free)
    rig.ok(f"DEFINE GATHER {free}")
    assert rig.ok("SIZE") == "0"
    rig.ok("DELETE GATHER")
    rig.ok("DEFINE GATHER")
    assert rig.ok("SIZE") == "0"
    rig.ok("DELETE GATHER")
    assert rig.ok("SIZE") == str(free)


@pytest.mark.parametrize("n", [0, 33, -1, True, 1.0, "1"])
def test_motors_are_numbered_1_to_32(rig, n):
    """A Turbo PMAC has motors #1..#32 (here ``N_MOTORS``); any other number is NotFound."""
    assert rig.c.motor(1) is not rig.c.motor(32)
    with pytest.raises(NotFound):
        rig.c.motor(n)


@pytest.mark.parametrize("value", [True, math.nan, math.inf, -math.inf, "1", None])
def test_a_variable_write_must_be_a_finite_number_and_changes_nothing(rig, value):
    """A write of anything but a finite number is refused naming ``value``; the variable
    keeps its value and the log is unchanged."""
    rig.c.set_variable("P1", 5)
    seq = rig.c.log.last_seq
    with pytest.raises(InvalidValue) as refused:
        rig.c.set_variable("P1", value)
    assert refused.value.details["field"] == "value"
    assert rig.c.get_variable("P1") == 5.0
    assert rig.c.log.last_seq == seq


def test_every_config_key_is_checked_also_after_a_processor_cost_key():
    """Processor-time costs (``cpu_<name>_us``) are checked against their bound and the keys
    after them are still checked: a bad cost, or an I8192 after a good cost, is refused
    naming the key."""
    with pytest.raises(InvalidValue) as refused:
        PmacController("pmac", {"cpu_plc_statement_us": -1})
    assert refused.value.details["field"] == "cpu_plc_statement_us"
    with pytest.raises(InvalidValue) as refused:
        PmacController("pmac", {"cpu_plc_statement_us": 5, "i8192": 1})
    assert refused.value.details["field"] == "i8192"


def test_a_controller_log_holds_at_least_100000_events_by_default():
    """API.md: the event log keeps at least the last 100 000 events."""
    assert PmacController("pmac").log.capacity >= 100_000
