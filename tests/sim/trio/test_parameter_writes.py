"""Parameters users write: ENDMOVE at rest steps DPOS (TRM MC216 listing p. 8-159, DPOS: "a
value can be forced to create a step change in position by writing to the ENDMOVE parameter if
no moves are currently in progress on the axis"), and REP_DIST held in whole encoder edges
(Trio KB "What is the accuracy on the UNITS / REP_DIST?": stored as INT(value x UNITS), read
back as stored / UNITS; to set an exact count write it with UNITS=1)."""

from __future__ import annotations

from tests.sim.trio.conftest import fields, make, run_to


def ask(c, expr: str) -> str:
    r = c.terminal(f"? {expr}")
    assert r.error is None, r.error
    return r.reply


def test_endmove_written_at_rest_steps_dpos_and_moves_go_on_from_there():
    c = make()
    assert c.terminal("ENDMOVE=25").error is None
    assert ask(c, "DPOS") == "25.0000" and ask(c, "MPOS") == "25.0000"
    assert ask(c, "ENDMOVE") == "25.0000"
    assert [f for _t, f in fields(c, "endmove")] == [{"axis": 0, "dpos": 25.0}]
    c.terminal("MOVE(10)")
    run_to(c, 0.5)
    assert c.axis(0)["dpos"] == 35.0
    c.terminal("ENDMOVE AXIS(2)=-7")
    assert c.axis(2)["dpos"] == -7.0 and c.axis(0)["dpos"] == 35.0


def test_endmove_steps_to_a_whole_encoder_edge():
    c = make()
    c.terminal("UNITS=1000")
    c.terminal("ENDMOVE=1.23456")  # 1234.56 edges: the nearest edge is 1235
    assert ask(c, "DPOS") == "1.2350"


def test_endmove_cannot_be_written_while_a_move_is_in_progress():
    c = make()
    c.terminal("MOVE(100)")
    run_to(c, 0.02)
    r = c.terminal("ENDMOVE=5")
    assert r.error is not None and "ENDMOVE" in r.error and "in progress" in r.error
    run_to(c, 1.0)
    assert c.axis(0)["dpos"] == 100.0 and fields(c, "endmove") == []


def test_rep_dist_reads_back_in_whole_counts_and_keeps_its_count_over_units_changes():
    c = make()
    c.terminal("UNITS=1000")
    c.terminal("REP_DIST=12.34567")  # INT(12345.67) = 12345 edges
    assert ask(c, "REP_DIST") == "12.3450"
    c.terminal("UNITS=500")  # the count stays: 12345 / 500
    assert ask(c, "REP_DIST") == "24.6900"
    c.terminal("UNITS=1")
    c.terminal("REP_DIST=360.9")  # an exact count is written with UNITS=1: INT(360.9)
    assert ask(c, "REP_DIST") == "360.0000"


def test_a_program_writes_endmove_before_its_first_move():
    c = make()
    c.store_program("HOME", "ENDMOVE=100\nMOVE(-40)\nWAIT IDLE\nVR(0)=DPOS\n")
    c.run_program("HOME")
    run_to(c, 1.0)
    assert c.get_variable("VR(0)") == 60.0


def test_a_units_too_small_for_a_distance_held_in_edges_is_refused_and_changes_nothing():
    """A distance held in whole edges reads back as count / UNITS (Trio KB, module docstring):
    a denormal UNITS would make REP_DIST infinite and every DPOS read fail, so UNITS below
    1e-9 is refused, from BASIC (the card's out-of-range error) and from the API alike
    (sim/bounds.py TRIO_UNITS)."""
    c = make()
    c.terminal("UNITS=1000")
    r = c.terminal("UNITS=1e-320")
    assert r.error is not None and "Parameter out of range: UNITS" in r.error
    assert ask(c, "UNITS") == "1000.0000" and ask(c, "DPOS") == "0.0000"
    try:
        c.set_axis(1, units=5e-324, speed=5e-324)
    except Exception as exc:  # noqa: BLE001 - the type is the API's 422
        assert type(exc).__name__ == "InvalidValue" and exc.details == {"field": "units"}
    else:
        raise AssertionError("a denormal UNITS was accepted")
    assert c.axis(1)["units"] == 1.0 and c.axis(1)["speed"] != 5e-324
    c.terminal("UNITS=1e-9")  # the smallest accepted: REP_DIST still reads back finite
    assert c.terminal("? REP_DIST").error is None and c.terminal("? DPOS").error is None
