"""DATUM(1..6) against the simulated datum input and Z mark (TJ2P5-247; phases ``[BK]`` as
written down in :mod:`motionsim.sim.trio.datum`), asserted on the event log."""

from __future__ import annotations

import pytest

from tests.sim.trio.conftest import cycle, fields, make, run_to


def _homing(mode: int, clear_at_start: bool = True):
    c = make()
    c.terminal("DATUM_IN=5")
    c.set_variable("IN(5)", 1 if clear_at_start else 0)  # active low: 1 = switch clear
    assert c.terminal(f"DATUM({mode})").error is None
    return c


def test_tj2p5_247_datum4_reverse_at_speed_to_the_input_then_creep_off_it_and_zero():
    c = _homing(4)
    run_to(c, 0.05)
    assert c.axis(0)["mtype"] == 12 and c.axis(0)["dpos"] < -40  # reverse at SPEED
    run_to(c, 0.1005)
    c.set_variable("IN(5)", 0)  # the switch is reached (input OFF)
    run_to(c, 0.2)
    # decelerated at DECEL (10 ms), then forward at CREEP (10 units/s)
    assert c.terminal("? VP_SPEED").reply == "10.0000"
    assert c.axis(0)["dpos"] > -100.0
    run_to(c, 0.3005)
    c.set_variable("IN(5)", 1)  # off the switch: the datum
    run_to(c, 1.0)
    (t_datum, d), = fields(c, "datum", axis=0)
    assert cycle(c, t_datum) == 301 and d["mode"] == 4
    assert d["at"] == pytest.approx(-100.0 + 10 * 0.19 - 0.0005, abs=1e-6)
    starts = [(cycle(c, t), f["mtype"]) for t, f in fields(c, "move_start", axis=0)]
    ends = [cycle(c, t) for t, _ in fields(c, "move_end", axis=0)]
    assert starts == [(1, 12)] and ends == [302]
    assert c.axis(0)["mtype"] == 0 and c.axis(0)["dpos"] == 0.0
    assert c.terminal("? AXISSTATUS").reply == "0.0000"


def test_tj2p5_247_datum3_already_on_the_switch_creeps_back_off_it():
    c = _homing(3, clear_at_start=False)
    run_to(c, 0.1005)
    assert c.axis(0)["dpos"] == pytest.approx(-0.99, abs=0.001)  # reverse at CREEP from 1
    c.set_variable("IN(5)", 1)
    run_to(c, 0.5)
    assert len(fields(c, "datum", axis=0)) == 1
    assert c.axis(0)["mtype"] == 0 and c.axis(0)["dpos"] == 0.0


def test_tj2p5_247_datum1_creeps_forward_to_the_z_mark():
    """No input: CREEP (10 units/s) forward from 0.3 to the next Z mark, a whole unit [INF]
    (UNITS 10, so that 0.3 is three whole edges)."""
    c = make(units=10)
    c.terminal("MOVEABS(0.3)")
    run_to(c, 0.5)
    c.terminal("DATUM(1)")
    run_to(c, 2.0)
    (t, d), = fields(c, "datum", axis=0)
    assert d["at"] == pytest.approx(1.0, abs=0.011)  # found in the period it crossed 1.0
    assert cycle(c, t) == pytest.approx(501 + 70, abs=1)
    assert c.axis(0)["dpos"] == 0.0


def test_tj2p5_247_datum6_reverse_to_the_input_then_on_to_the_z_mark():
    c = _homing(6)
    run_to(c, 0.0505)
    c.set_variable("IN(5)", 0)
    run_to(c, 0.2005)
    c.set_variable("IN(5)", 1)  # off the switch: now on to the next Z mark, forward
    run_to(c, 0.2505)
    assert fields(c, "datum") == []
    run_to(c, 3.0)
    (_t, d), = fields(c, "datum", axis=0)
    assert d["at"] == pytest.approx(round(d["at"]), abs=0.011)  # a whole unit: a Z mark
    assert c.axis(0)["dpos"] == 0.0


def test_datum_is_cancelled_to_rest_without_a_datum():
    c = _homing(3)
    run_to(c, 0.0505)
    c.terminal("CANCEL")
    run_to(c, 0.2)
    assert c.axis(0)["mtype"] == 0 and fields(c, "datum") == []
    assert c.axis(0)["dpos"] == pytest.approx(50.0, abs=1.0)  # ramped down, not zeroed


@pytest.mark.parametrize(("cmd", "text"), [("DATUM(3)", "DATUM_IN"), ("DATUM(7)", "DATUM(7)"),
                                           ("DATUM(2.5)", "DATUM(2.5)")])
def test_bad_datum_is_an_error_and_buffers_nothing(cmd, text):
    c = make()
    r = c.terminal(cmd)
    assert r.error is not None and text in r.error
    run_to(c, 0.1)
    assert fields(c, "move_start") == []


def test_invert_in_makes_the_datum_input_active_high():
    c = make()
    c.terminal("DATUM_IN=7")
    c.terminal("INVERT_IN(7,ON)")
    c.terminal("DATUM(3)")  # IN(7) is 0 (reads 1 inverted): clear
    run_to(c, 0.0505)
    assert c.axis(0)["dpos"] > 20
    c.set_variable("IN(7)", 1)  # reads 0 inverted: reached
    run_to(c, 0.1005)
    c.set_variable("IN(7)", 0)
    run_to(c, 0.5)
    assert len(fields(c, "datum")) == 1 and c.axis(0)["dpos"] == 0.0
