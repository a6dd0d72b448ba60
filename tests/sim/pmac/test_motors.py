"""On-line motor commands in virtual time: jog, home, kill, open loop and the ``?`` word.

Facts: TSRM p100-101 (Ixx19-Ixx23), p152 (Ixx92), p270-284 (motor commands, ``?``), p377
(``O``); TUM p217 (stop commands); PUM-V p128-130 (homing); spec pmac.md §11.3, §11.9.
Times are asserted in servo cycles; the ``jog`` / ``home`` / ``motor`` events carry them.
"""

from __future__ import annotations

import math

import pytest

#: Jog set-up with round numbers: 10 cts/ms, 100 ms ramps (0.1 cts/ms² < Ixx19), no Ixx92.
JOG = "I122=10 I120=100 I121=0 I119=1 I192=0"


def status(rig, n: int = 1) -> tuple[int, int]:
    text = rig.ok(f"#{n}?")
    assert len(text) == 12
    return int(text[:6], 16), int(text[6:], 16)


def jog_events(rig, *types: str):
    return rig.events(*(types or ("jog", "home", "motor")))


def test_jog_plus_ramps_over_ixx20_to_ixx22_and_runs_on(rig):
    rig.ok(JOG)
    rig.ok("#1J+")
    (k0, _, start), = jog_events(rig, "jog")
    assert start == {"motor": 1, "state": "start", "command": "J+", "position": 0.0}
    t0 = k0 * rig.period
    rig.run_for(t0 + 0.3 - rig.c.env.now)
    # after the 100 ms ramp (0.5·10·100 = 500 counts) it runs at 10 cts/ms
    assert rig.c.motor_position(1, t0 + 0.3) == pytest.approx(500 + 10 * (300 - 100))
    assert rig.c.motor_position(1, t0 + 0.05) == pytest.approx(0.5 * 0.1 * 50**2)
    assert float(rig.ok("#1V")) == pytest.approx(10 * rig.period * 1000, abs=1e-3)
    w1, w2 = status(rig)
    assert not w1 & (1 << 13) and not w2 & 1  # moving: desired velocity not zero, not in position
    assert jog_events(rig, "jog")[1:] == []  # an indefinite jog has no end


def test_ixx19_clamps_the_jog_acceleration_and_stretches_the_ramp(rig):
    """TSRM p100: Ixx20=100, Ixx21=0, Ixx22=50 asks 0.5 cts/ms²; Ixx19=0.25 makes it 200 ms."""
    rig.ok("I122=50 I120=100 I121=0 I119=0.25 I192=0")
    rig.ok("#1J+")
    t0 = jog_events(rig, "jog")[0][0] * rig.period
    rig.run_for(t0 + 0.1 - rig.c.env.now)
    assert float(rig.ok("#1V")) / (rig.period * 1000) == pytest.approx(25, abs=0.1)
    rig.run_for(0.15)
    assert float(rig.ok("#1V")) / (rig.period * 1000) == pytest.approx(50, abs=0.01)


def test_ixx21_s_curve_time_sets_the_ramp_when_twice_it_exceeds_ixx20(rig):
    rig.ok("I122=10 I120=20 I121=50 I119=1 I192=0")  # max(20, 2·50) = 100 ms
    rig.ok("#1J^1000")
    rig.run_until_idle()
    (k0, _, _), (k1, _, end) = jog_events(rig, "jog")
    assert end["position"] == pytest.approx(1000.0)
    assert (k1 - k0) == math.ceil(0.2 / rig.period - 1e-6)  # a 100+100 ms triangle


def test_definite_jog_ends_at_rest_on_its_target_at_a_servo_cycle(rig):
    rig.ok(JOG)
    rig.ok("#1J^3000")  # 100 ms up, 200 ms at speed, 100 ms down
    rig.run_until_idle()
    (k0, _, s), (k1, _, e) = jog_events(rig, "jog")
    assert (s["command"], e["command"], e["state"]) == ("J^", "J^", "end")
    assert k1 == k0 + math.ceil(0.4 / rig.period - 1e-6)
    assert rig.ok("#1P") == "3000"
    assert rig.ok("#1V") == "0"
    w1, w2 = status(rig)
    assert w1 & (1 << 13) and w2 & 1  # desired velocity zero, in position


def test_j_equals_position_and_j_equals_back_to_the_pre_jog_position(rig):
    rig.ok(JOG)
    rig.ok("#1J=-2500")
    rig.run_until_idle()
    assert rig.ok("#1P") == "-2500"
    rig.ok("#1J:500")  # relative to the commanded position
    rig.run_until_idle()
    assert rig.ok("#1P") == "-2000"
    rig.ok("#1J=")  # the pre-jog position: where the last jog from rest started
    rig.run_until_idle()
    assert rig.ok("#1P") == "-2500"
    assert [e["command"] for _, _, e in jog_events(rig, "jog")] == ["J="] * 2 + ["J:"] * 2 + [
        "J="
    ] * 2


def test_j_slash_ramps_a_jog_to_rest(rig):
    rig.ok(JOG)
    rig.ok("#1J-")
    rig.run_for(0.5)
    rig.ok("#1J/")
    p_stop_cmd = float(rig.ok("#1P"))
    rig.run_until_idle()
    _, _, end = jog_events(rig, "jog")[-1]
    assert end["state"] == "end" and end["command"] == "J/"
    # from full speed a 100 ms ramp covers 500 counts (give or take the reply's cycle)
    assert float(rig.ok("#1P")) == pytest.approx(p_stop_cmd - 500, abs=30)


def test_ixx92_delays_the_start_of_a_jog_from_rest(rig):
    rig.ok("I122=10 I120=100 I121=0 I119=1 I192=10")
    reply = rig.cmd("#1J+")
    t_cmd = reply.t_done
    assert jog_events(rig, "jog") == []
    rig.run_for(0.05)
    (k0, _, _), = jog_events(rig, "jog")
    assert k0 == math.ceil((t_cmd + 0.010) / rig.period - 1e-6)


def test_home_search_at_ixx23_re_zeroes_at_capture_plus_ixx26_and_stops_there(rig):
    rig.ok("I123=-20 I120=100 I121=0 I119=1 I192=0 I126=160")  # home offset 160/16 = 10 cts
    rig.ok(JOG + " #1J=5000")
    rig.run_until_idle()
    rig.ok("#1HM")
    w1, w2 = status(rig)
    assert w1 & (1 << 10) and not w2 & (1 << 10)  # searching, home not complete
    rig.run_until_idle()
    kinds = [(t, e.get("state"), e.get("command")) for _, t, e in jog_events(rig, "jog", "home")]
    assert kinds[-3:] == [("jog", "start", "HM"), ("home", "triggered", None), ("jog", "end", "HM")]
    (k_start, _, _), (k_trig, _, trig) = jog_events(rig, "jog", "home")[-3:-1]
    # the trigger comes when the search is at speed (-20 cts/ms after the Ixx20 100 ms ramp)
    assert k_trig == math.ceil((k_start * rig.period + 0.1) / rig.period - 1e-6)
    t_at_speed = k_start * rig.period + 0.1
    beyond = 20_000 * (k_trig * rig.period - t_at_speed)  # counts run at speed after that
    assert trig["position"] == pytest.approx(5000 - 0.5 * 20 * 100 - beyond, abs=1e-3)
    assert rig.ok("#1P") == "0"  # at rest on the new zero
    w1, w2 = status(rig)
    assert not w1 & (1 << 10) and w2 & (1 << 10) and w2 & 1


def test_home_zero_makes_the_present_position_zero_without_motion(rig):
    rig.ok(JOG + " #1J=700")
    rig.run_until_idle()
    n = len(rig.c.log.events())
    rig.ok("#1HMZ")
    assert rig.ok("#1P") == "0"
    assert status(rig)[1] & (1 << 10)
    assert [e.type for e in rig.c.log.events()[n:]] == []


def test_kill_opens_the_loop_disables_the_amplifier_and_leaves_the_motor_where_it_is(rig):
    rig.ok(JOG)
    rig.ok("#1J+")
    rig.run_for(0.3)
    rig.ok("#1K")
    p = rig.ok("#1P")
    rig.run_for(0.5)
    assert rig.ok("#1P") == p
    w1, w2 = status(rig)
    assert not w1 & (1 << 19) and w1 & (1 << 18) and not w2 & 1
    assert jog_events(rig, "motor") == [(jog_events(rig, "motor")[0][0], "motor",
                                         {"motor": 1, "state": "killed"})]
    rig.ok("#1J/")  # J/ closes the loop again (TUM p217)
    w1, _ = status(rig)
    assert w1 & (1 << 19) and not w1 & (1 << 18)
    assert jog_events(rig, "motor")[-1][2] == {"motor": 1, "state": "closed_loop"}


def test_open_loop_command_and_dollar_closes_the_loop(rig):
    rig.ok("#2O50")
    w1, _ = status(rig, 2)
    assert w1 & (1 << 18) and w1 & (1 << 19)  # open loop, amplifier still enabled
    rig.ok("#2$")
    w1, w2 = status(rig, 2)
    assert not w1 & (1 << 18) and w2 & 1
    assert [e["state"] for _, _, e in jog_events(rig, "motor")] == ["open_loop", "closed_loop"]


def test_dollar_star_without_an_absolute_sensor_zeroes_and_leaves_the_motor_killed(rig):
    rig.ok(JOG + " #3J=400")
    rig.run_until_idle()
    rig.ok("#3HMZ #3$*")
    assert rig.ok("#3P") == "0"
    w1, w2 = status(rig, 3)
    assert not w1 & (1 << 19) and not w2 & (1 << 10)


def test_motor_commands_are_refused_err001_while_its_cs_runs_a_program(rig):
    rig.ok("&1 #1->1000X")
    rig.rotary_setup()
    rig.ok("OPEN ROT")
    rig.ok("TM1000 X1 X2")
    rig.ok("CLOSE &1R")
    rig.run_for(0.1)
    n = len(rig.c.log.events())
    for command in ("#1J+", "#1HM", "#1K", "#1O10", "#1$"):
        assert rig.cmd(command).error == "ERR001", command
    assert [e.type for e in rig.c.log.events()[n:] if e.type in ("jog", "motor", "home")] == []
    assert rig.cmd("#2J+").error is None  # a motor of no CS jogs


def test_status_word_two_carries_cs_axis_code_and_assignment(rig):
    """TSRM p284: ``81200001C401`` — CS 1, A-axis (code 1), assigned, home complete,
    in position; here with Ixx34 = 1 (integration mode, bit 16 of word 1)."""
    rig.ok("&1 #1->A I134=1 #1HMZ")
    w1, w2 = status(rig)
    assert f"{w2:06X}" == "01C401"
    assert w1 & 0x812000 == 0x812000
    rig.ok("&3 #4->1000X")
    assert status(rig, 4)[1] >> 16 == 0x27  # CS 3 - 1 = 2, XYZ code 7


def test_jog_of_an_unknown_form_is_a_syntax_error_that_changes_nothing(rig):
    n = len(rig.c.log.events())
    for bad in ("#1J=(P1)", "#1J^", "#33J+", "#1O"):
        assert rig.cmd(bad).error == "ERR003", bad
    assert rig.c.log.events()[n:] == []


def test_software_limit_ixx13_stops_a_jog_at_ixx15_and_flags_it(rig):
    """PSRM Ix13/Ix15, TSRM p281-284: past Ixx13 the motor decelerates at Ixx15; word 1 bit 21
    "positive end limit set" while it is beyond, word 2 bit 11 "stopped on position limit"
    until the next move command."""
    rig.ok(JOG + " I115=0.1 I113=2000")
    rig.ok("#1J+")
    rig.run_until_idle()
    (k0, _, _), (k1, _, end) = jog_events(rig, "jog")
    t_cross = k0 * rig.period + 0.1 + (2000 - 500) / 10_000  # ramp, then 10 cts/ms
    k_hit = math.ceil(t_cross / rig.period - 1e-6)
    assert k1 == math.ceil((k_hit * rig.period + 0.1) / rig.period - 1e-6)  # 10/0.1 ms
    assert end["position"] == pytest.approx(2000 + 500, abs=10 * rig.period * 1000)
    w1, w2 = status(rig)
    assert w1 & (1 << 21) and not w1 & (1 << 22) and w2 & (1 << 11)
    rig.ok("#1J=0")
    w1, w2 = status(rig)
    assert not w2 & (1 << 11)
    rig.run_until_idle()
    assert not status(rig)[0] & (1 << 21) and rig.ok("#1P") == "0"


def test_software_limit_ixx14_also_stops_a_definite_jog_short_of_its_target(rig):
    rig.ok(JOG + " I115=1 I114=-1000")
    rig.ok("#1J=-5000")
    rig.run_until_idle()
    p = float(rig.ok("#1P"))
    assert -1100 < p < -1000
    assert status(rig)[0] & (1 << 22)


def test_a_home_search_with_no_ixx92_delay_starts_once(rig):
    """PUM-V p128: one search, one "start" on the log, even when Ixx92 = 0 makes the motor
    start on the command's own servo cycle."""
    rig.ok(JOG + " I123=10")
    rig.ok("#1HM")
    rig.run_until_idle()
    states = [(e["command"], e["state"]) for _, _, e in jog_events(rig, "jog")]
    assert states == [("HM", "start"), ("HM", "end")]
