"""Variable jogs and jog-until-trigger, in virtual time (PSRM p241; TSRM p282; spec §11.9).

``J=*`` / ``J^*`` / ``J:*`` take their target or distance from the motor's variable jog
register Mxx72 (``L:$0000D7`` + $80 per motor: Delta Tau's suggested ``M172->L:$0000D7``);
a definite jog followed by ``^{d}`` runs until a trigger and then moves to the captured
position + d, without changing the motor's zero. No flag input is simulated: the trigger
comes the first servo cycle the jog is at full speed ``[INF]`` (as for ``HM``). ``?`` word 1
bit 10 is set while the trigger is searched; word 2 bit 7 from the start of the move until a
trigger is found, and stays set when none is.
"""

from __future__ import annotations

import math

import pytest

from tests.sim.pmac.test_motors import JOG, jog_events, status

MXX72 = "M172->L:$0000D7 M272->L:$000157"


def test_psrm_p241_j_hat_star_jogs_the_distance_held_in_mxx72(rig):
    rig.ok(JOG)
    rig.ok(MXX72)
    rig.ok("M172=3000")
    rig.ok("#1J^*")
    rig.run_until_idle()
    (k0, _, s), (k1, _, e) = jog_events(rig, "jog")
    assert (s["command"], e["state"], e["position"]) == ("J^", "end", 3000.0)
    assert k1 == k0 + math.ceil(0.4 / rig.period - 1e-6)  # 100 ms up, 200 at speed, 100 down


def test_psrm_p241_j_equals_star_goes_to_the_position_in_mxx72_of_its_own_motor(rig):
    rig.ok(JOG)
    rig.ok(MXX72)
    rig.ok("M172=111 M272=-2500")
    rig.ok("#2J=*")
    rig.run_until_idle()
    assert rig.ok("#2P") == "-2500"
    assert rig.ok("#1P") == "0"


def test_mxx72_is_read_when_the_command_runs_not_when_it_was_written_before(rig):
    rig.ok(JOG)
    rig.ok(MXX72)
    rig.ok("M172=1000")
    rig.ok("#1J:*")
    rig.run_until_idle()
    rig.ok("M172=500")
    rig.ok("#1J:*")
    rig.run_until_idle()
    assert rig.ok("#1P") == "1500"


def test_tsrm_p282_jog_until_trigger_moves_to_the_capture_plus_the_offset(rig):
    """``J^100000^-200``: the trigger at full speed (the end of the 100-ms ramp, 500 counts
    out), then the motor stops and comes back to capture − 200; the zero is unchanged."""
    rig.ok(JOG)
    rig.ok("#1J^100000^-200")
    rig.run_until_idle()
    events = jog_events(rig, "jog", "home")
    (k0, _, start), (kt, _, trig), (_, _, end) = events
    assert (start["state"], trig["state"], end["state"]) == ("start", "triggered", "end")
    assert kt == k0 + math.ceil(0.1 / rig.period - 1e-6)  # first servo cycle at full speed
    capture = trig["position"]
    t_full = k0 * rig.period + 0.1  # 500 counts out, at 10 counts/ms from then on
    assert capture == pytest.approx(500 + 10_000 * (kt * rig.period - t_full), abs=1e-3)
    assert end["position"] == pytest.approx(capture - 200)
    assert float(rig.ok("#1P")) == pytest.approx(capture - 200, abs=0.5)
    w1, w2 = status(rig)
    assert not w1 & (1 << 10) and not w2 & (1 << 7)  # trigger found: both flags clear
    assert not w2 & (1 << 10)  # not a home: "home complete" stays clear


def test_tsrm_p282_the_trigger_flags_while_searching(rig):
    rig.ok(JOG)
    rig.ok("#1J^100000^0")
    rig.run_for(0.05)  # on the ramp: not yet at full speed
    w1, w2 = status(rig)
    assert w1 & (1 << 10) and w2 & (1 << 7)  # trigger search in progress, trigger move


def test_tsrm_p282_a_move_that_finds_no_trigger_ends_at_its_target_with_bit_7_set(rig):
    """A 600-count jog never reaches full speed (a triangle): no trigger; it ends at its
    target and word 2 bit 7 stays 1 until the next move command."""
    rig.ok(JOG)
    rig.ok("#1J^600^0")
    rig.run_until_idle()
    assert [e["state"] for _, _, e in jog_events(rig, "jog")] == ["start", "end"]
    assert rig.ok("#1P") == "600"
    w1, w2 = status(rig)
    assert w2 & (1 << 7) and not w1 & (1 << 10)
    rig.ok("#1J^100")
    rig.run_until_idle()
    assert not status(rig)[1] & (1 << 7)


@pytest.mark.parametrize("line", ["#1J+^100", "#1J^100^(P1)"])
def test_psrm_p241_only_a_definite_jog_takes_a_constant_trigger_offset(rig, line):
    reply = rig.cmd(line)
    assert reply.error == "ERR003"
    assert [e for e in jog_events(rig, "jog")] == []  # refused: nothing moves
