"""Trio SCOPE and TRIGGER (issue 34): parameters sampled into TABLE every ``period`` servo
periods, one shot or automatic, in virtual time.

The rules are the Trio help page of SCOPE (Trio MC4 help, "SCOPE": the syntax, "samples are
taken until the table range is filled", example 1: two parameters in 0..1000 share the range,
the first in TABLE(0)..(499), the second in (500)..(999); example 2: SCOPE(OFF) stops TRIGGER
starting a capture; example 3: SCOPE(ON, 20) changes the period on the fly; "TRIGGER may
specify one-shot or automatic"). Samples are checked against the ``move_start`` /
``move_end`` events of the move they record and against VR values written at known instants.
"""

from __future__ import annotations

import pytest
from motionsim.sim.errors import ParseError

from .conftest import cycle, fields, make, run_to


def cmd(c, text: str) -> None:
    reply = c.terminal(text)
    assert reply.done and reply.error is None, (text, reply.reply, reply.error)


def scope_events(c) -> list[tuple[int, dict]]:
    return [(cycle(c, t), f) for t, f in fields(c, "scope")]


def test_the_parameters_share_the_table_range_in_order(trio):
    """Example 1: SCOPE(ON, 10, 0, 1000, MPOS AXIS(5), DPOS AXIS(5)) -> 500 samples each,
    MPOS in TABLE(0..499), DPOS in TABLE(500..999), every 10 servo periods."""
    c = make(axes=6)
    cmd(c, "SCOPE(ON, 10, 0, 1000, MPOS AXIS(5), DPOS AXIS(5))")
    cmd(c, "VR(0)=1")
    k_trigger = c.clock.index(c.env.now)
    cmd(c, "TRIGGER")
    cmd(c, "MOVE(100) AXIS(5)")
    run_to(c, 6.0)
    rec = c.scope.recording()
    assert rec.names == ("MPOS AXIS(5)", "DPOS AXIS(5)")
    assert len(rec.cycles) == 500 and rec.cycles[0] == k_trigger + 1
    assert rec.cycles == tuple(range(rec.cycles[0], rec.cycles[0] + 5000, 10))
    assert c.table[0] == rec.columns[0][0] and c.table[999] == rec.columns[1][-1]
    assert 1000 not in c.table
    (k_start, _), = [(cycle(c, t), f) for t, f in fields(c, "move_start", axis=5)]
    (k_end, _), = [(cycle(c, t), f) for t, f in fields(c, "move_end", axis=5)]
    dpos = dict(zip(rec.cycles, rec.columns[1], strict=True))
    assert all(v == 0.0 for k, v in dpos.items() if k <= k_start)
    assert all(v == 100.0 for k, v in dpos.items() if k >= k_end)
    during = [v for k, v in sorted(dpos.items()) if k_start < k < k_end]
    assert during == sorted(during) and 0 < during[0] < during[-1] < 100
    states = [f["state"] for _, f in scope_events(c)]
    assert states == ["armed", "triggered", "done"]
    k_done = scope_events(c)[-1][0]
    assert k_done == rec.cycles[-1]


def test_one_shot_stops_when_the_range_is_full_and_stays_armed(trio):
    c = trio
    cmd(c, "SCOPE(ON, 2, 100, 110, VR(1))")
    cmd(c, "TRIGGER")
    run_to(c, 0.1)
    rec = c.scope.recording()
    assert len(rec.cycles) == 10 and not rec.running and rec.armed
    assert sorted(k for k in c.table) == list(range(100, 110))
    cmd(c, "VR(1)=5")
    cmd(c, "TRIGGER")  # armed still: a second capture from the start of the range
    run_to(c, 0.2)
    assert [c.table[n] for n in range(100, 110)] == [5.0] * 10


def test_trigger_1_is_automatic_and_goes_round_until_scope_off(trio):
    c = trio
    cmd(c, "SCOPE(ON, 1, 0, 4, VR(2))")
    cmd(c, "TRIGGER(1)")
    run_to(c, 0.0105)
    cmd(c, "VR(2)=7")
    run_to(c, 0.020)
    rec = c.scope.recording()
    assert rec.running and rec.cyclic and len(rec.cycles) == 4
    assert rec.cycles == tuple(range(rec.cycles[0], rec.cycles[0] + 4))
    assert rec.columns == ((7.0, 7.0, 7.0, 7.0),)
    cmd(c, "SCOPE(OFF)")
    stored = dict(c.table)
    run_to(c, 0.05)
    assert c.table == stored and not c.scope.running
    assert [f["state"] for _, f in scope_events(c)][-1] == "off"


def test_scope_on_period_changes_the_period_on_the_fly(trio):
    """Example 3: SCOPE(ON, 10 ...) TRIGGER ... SCOPE(ON, 20): later samples 20 apart."""
    c = trio
    cmd(c, "SCOPE(ON, 10, 0, 100, VR(3))")
    cmd(c, "TRIGGER")
    run_to(c, 0.0505)
    cmd(c, "SCOPE(ON, 20)")
    run_to(c, 0.3)
    cycles = c.scope.recording().cycles
    steps = {b - a for a, b in zip(cycles, cycles[1:], strict=False)}
    assert steps == {10, 20}


def test_scope_off_keeps_trigger_from_starting_a_capture(trio):
    """Example 2."""
    c = trio
    cmd(c, "SCOPE(ON, 1, 0, 10, VR(1))")
    cmd(c, "SCOPE(OFF)")
    cmd(c, "TRIGGER")
    run_to(c, 0.05)
    assert c.table == {} and not c.scope.running


def test_the_samples_are_readable_as_table_from_basic_and_the_variable_resource(trio):
    c = trio
    cmd(c, "VR(4)=2.5")
    cmd(c, "SCOPE(ON, 1, 20, 23, VR(4))")
    cmd(c, "TRIGGER")
    run_to(c, 0.01)
    reply = c.terminal("PRINT TABLE(21)")
    assert reply.reply.strip() == "2.5000"
    assert c.get_variable("TABLE(22)") == 2.5


def test_a_program_sets_up_and_triggers_the_scope(trio):
    c = trio
    c.store_program("CAP", "SCOPE(ON, 5, 0, 50, MPOS, DPOS)\nTRIGGER\nMOVE(20)\nWAIT IDLE\n")
    c.run_program("CAP")
    run_to(c, 1.0)
    rec = c.scope.recording()
    assert rec.names == ("MPOS", "DPOS") and len(rec.cycles) == 25
    assert rec.columns[1][-1] == 20.0


@pytest.mark.parametrize(("text", "message"), [
    ("SCOPE(ON, 0, 0, 10, VR(1))", "period"),
    ("SCOPE(ON, 1, 0, 20000, VR(1))", "TABLE range"),
    ("SCOPE(ON, 1, 10, 5, VR(1))", "TABLE range"),
    ("SCOPE(ON, 1, 0, 1, VR(1), VR(2))", "holds no sample"),
    ("SCOPE(ON, 1, 0, 10, MPOS AXIS(40))", ""),
    ("SCOPE(ON, 5)", "the first time"),
    ("TRIGGER(2)", "TRIGGER(2)"),
])
def test_bad_scope_arguments_are_run_time_errors_and_change_nothing(trio, text, message):
    c = trio
    reply = c.terminal(text)
    assert reply.error is not None and message in reply.error
    assert not c.scope.armed and c.table == {}


@pytest.mark.parametrize("text", ["SCOPE(ON, 1, 0)", "SCOPE(ON, 1, 0, 10)",
                                  "SCOPE(ON,1,0,100,VR(1),VR(1),VR(1),VR(1),VR(1),VR(1),"
                                  "VR(1),VR(1),VR(1))"])
def test_a_scope_with_the_wrong_number_of_arguments_is_a_parse_error(trio, text):
    with pytest.raises(ParseError) as exc:
        trio.store_program("BAD", text + "\n")
    assert "SCOPE takes" in str(exc.value)


def test_scope_pos_is_the_table_entry_the_next_sample_goes_to(trio):
    """SCOPE_POS (the help page's See Also): the first parameter's next TABLE entry while the
    capture runs; one past the last once a one-shot capture is done [INF]."""
    c = trio
    cmd(c, "SCOPE(ON, 1, 100, 120, VR(1), VR(2))")  # 10 entries each: 100..109, 110..119
    assert c.terminal("PRINT SCOPE_POS").reply.strip() == "100.0000"
    cmd(c, "TRIGGER")
    run_to(c, 0.0035)  # samples at servo periods 1, 2, 3
    assert len(c.scope.recording().cycles) == 3
    assert c.terminal("PRINT SCOPE_POS").reply.strip() == "103.0000"
    run_to(c, 0.1)
    assert c.terminal("PRINT SCOPE_POS").reply.strip() == "110.0000"


def test_serial_number_and_system_error_read_their_own_values_while_a_scope_runs(trio):
    """SERIAL_NUMBER (a simulated board has none) and SYSTEM_ERROR (no system error is
    modelled) read 0 ``[INF]``, spec §10.11 "system:" — not the SCOPE's next TABLE entry."""
    c = trio
    cmd(c, "SCOPE(ON, 1, 100, 120, VR(1), VR(2))")
    assert c.terminal("PRINT SCOPE_POS").reply.strip() == "100.0000"
    for name in ("SERIAL_NUMBER", "SYSTEM_ERROR"):
        assert c.terminal(f"PRINT {name}").reply.strip() == "0.0000", name
