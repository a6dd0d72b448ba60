"""PmacController construction, config, reset and the background cycle."""

from __future__ import annotations

import pytest
from motionsim.sim.errors import InvalidValue, NotFound
from motionsim.sim.pmac import PmacController


def test_config_keys_are_lower_case_i_variables(make_rig):
    rig = make_rig(i16=3, i17=7, i8=5)
    assert rig.ok("I16 I17 I8") == "3\r7\r5"


@pytest.mark.parametrize("cfg, field", [({"x16": 1}, "x16"), ({"i16": "5"}, "i16"),
                                        ({"servo_hz": 0}, "servo_hz"), ({"i9000": 1}, "i9000")])
def test_unknown_or_bad_config_is_refused_naming_the_field(cfg, field):
    with pytest.raises(InvalidValue) as e:
        PmacController("p", cfg)
    assert e.value.details["field"] == field


def test_a_slow_background_answers_later_with_a_terminal_reply_event(make_rig):
    """API.md: a reply later than 1 s of simulated time is also a ``terminal_reply`` event."""
    rig = make_rig(background_cycles=3000)  # ≈ 1.33 s per background cycle
    reply = rig.c.terminal("I16")
    rig.run_for(1.0)
    assert not reply.done
    rig.run_for(1.0)
    assert (reply.reply, reply.error) == ("5", None)
    (ev,) = rig.c.log.events("terminal_reply")
    assert (ev["command"], ev["reply"], ev["error"]) == ("I16", "5", None)


def test_commands_queued_together_are_answered_one_per_background_cycle(rig):
    a, b = rig.c.terminal("I16"), rig.c.terminal("I17")
    rig.run_for(0.01)
    assert rig.cyc(b.t_done) == rig.cyc(a.t_done) + 1


def test_reset_is_a_power_cycle(rig):
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM100 X1", "X2"])
    rig.ok("R P1=5 I16=2")
    rig.run_for(0.05)
    rig.c.reset()
    assert rig.c.rotary(1) is None
    assert rig.c.coord(1)["program"] == {"state": "idle"}
    assert rig.c.get_variable("P1") == 0 and rig.c.get_variable("I16") == 5
    n = len(rig.c.log.events("move_end"))
    rig.run_for(2.0)
    assert len(rig.c.log.events("move_end")) == n  # nothing of the old program runs on
    assert len(rig.c.log.events("reset")) == 1


def test_variables_by_name():
    c = PmacController("p")
    c.set_variable("p5", 2.5)
    assert c.get_variable("P5") == 2.5
    with pytest.raises(NotFound):
        c.get_variable("X1")
    with pytest.raises(InvalidValue):
        c.set_variable("P1", float("nan"))
