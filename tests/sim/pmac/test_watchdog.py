"""The watchdog: no background cycle within I40 servo cycles (0 → 4096) trips the card.

Seed 003: a PLC 0 that is too long starves the background, "the watchdog timer will trip,
shutting down the card". TSRM p57 / TUM p215 (spec §9.6): motors killed, outputs off, the CPU
stops and will not communicate until the power is cycled.
"""

from __future__ import annotations

import pytest
from motionsim.sim.errors import Halted


def oversized_plc0(rig) -> int:
    """Enable a PLC 0 of 500 statements (≈ 1.66 ms > the 1.33 ms RTI); the enable's cycle."""
    rig.c.plcs.load(0, "\n".join(["M1=M1+1"] + ["P10=P10+1"] * 499))
    return rig.cyc(rig.cmd("ENABLE PLC 0").t_done)


def test_an_oversized_plc0_trips_the_watchdog_after_4096_servo_cycles(rig):
    k_enable = oversized_plc0(rig)
    rig.run_for(2.5)
    (trip,) = rig.events("watchdog")
    # The last background pass is the housekeeping right after the ENABLE's cycle (the next
    # servo cycle); from the next RTI on PLC 0 keeps the processor. I40 = 0 → 4096 cycles.
    assert trip[0] == k_enable + 1 + 4096
    assert trip[0] * rig.period == pytest.approx(1.81, abs=0.01)
    assert "I40" in trip[2]["reason"]


def test_i40_sets_the_watchdog_time(make_rig):
    rig = make_rig(i40=300)
    k_enable = oversized_plc0(rig)
    rig.run_for(0.5)
    (trip,) = rig.events("watchdog")
    assert trip[0] == k_enable + 1 + 300


def test_a_plc0_that_fits_never_trips(rig):
    """380 statements ≈ 1.26 ms: sluggish background, but it still cycles."""
    rig.c.plcs.load(0, "\n".join(["P10=P10+1"] * 380))
    rig.ok("ENABLE PLC 0")
    rig.run_for(3.0)
    assert rig.events("watchdog") == [] and rig.events("rti_overrun") == []
    assert rig.ok("I40") == "0"


def test_the_trip_kills_motion_stops_programs_and_turns_outputs_off(rig):
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM1000 X100", "X200", "X300"])
    rig.ok("M5=1 &1 R")
    oversized_plc0(rig)
    rig.run_for(2.5)
    trip_seq = rig.c.log.events("watchdog")[0].seq
    later = [(rig.cyc(e.t), e.type, dict(e.fields)) for e in rig.c.log.read(trip_seq).events]
    k_trip = rig.cyc(rig.c.log.events("watchdog")[0].t)
    assert ("program", {"cs": 1, "state": "aborted", "error": "watchdog"}) in [
        (t, f) for _, t, f in later
    ]
    outputs_off = {f["name"] for _, t, f in later if t == "mvar" and f["value"] == 0}
    assert {"M1", "M5"} <= outputs_off
    assert all(c == k_trip for c, _, _ in later)
    n = rig.c.log.last_seq
    rig.run_for(2.0)
    assert rig.c.log.last_seq == n  # the card is stopped: nothing happens any more
    assert rig.c.coord(1)["program"]["state"] == "aborted"


def test_a_tripped_card_answers_nothing_until_reset(rig):
    oversized_plc0(rig)
    rig.run_for(2.5)
    with pytest.raises(Halted) as e:
        rig.c.terminal("I16")
    assert e.value.code == "watchdog"
    with pytest.raises(Halted):
        rig.c.load_lines(1, ["X1"])
    assert rig.c.status()["watchdog"]["tripped"] is True
    rig.c.reset()
    assert rig.ok("I16") == "5"
    assert rig.c.status()["watchdog"]["tripped"] is False
    rig.run_for(3.0)
    assert len(rig.events("watchdog")) == 1  # PLCs were erased by the power cycle


def test_the_trip_freezes_commanded_positions_at_the_trip_instant(make_rig):
    """TSRM p57 / TUM p215: the trip kills the motors — no deceleration, no extrapolation of the
    cut-off move. The position read any time later is the profile's position at the trip
    instant (a twin card without the PLC 0, read at that instant, gives the same number); the
    move ends there (``move_end`` at the trip cycle) and the program reports the watchdog."""
    rig, twin = make_rig(), make_rig()
    for r in (rig, twin):
        r.rotary_setup()
        r.ok("&1 #1->X")
        r.c.load_lines(1, ["TM1000 X100", "X200", "X300"])
        r.ok("&1 R")
    oversized_plc0(rig)
    rig.run_for(2.5)
    t_trip = rig.c.status()["watchdog"]["t"]
    k_trip = rig.cyc(t_trip)
    twin.run_for(t_trip - twin.c.now)
    assert twin.c.now == pytest.approx(t_trip, abs=1e-12)
    x_trip = twin.c.positions(1)["X"]
    assert 100.0 < x_trip < 200.0  # the trip cut move 2 short
    assert rig.c.positions(1)["X"] == pytest.approx(x_trip, abs=1e-9)
    rig.run_for(1.0)
    assert rig.c.positions(1)["X"] == pytest.approx(x_trip, abs=1e-9)
    assert rig.events("move_start", "move_end")[-2:] == [
        (rig.cyc(rig.c.log.events("move_start")[-1].t), "move_start", {"cs": 1, "n": 2}),
        (k_trip, "move_end", {"cs": 1, "n": 2}),
    ]
    assert rig.events("program")[-1] == (
        k_trip, "program", {"cs": 1, "state": "aborted", "error": "watchdog"}
    )
    assert rig.c.coord(1)["program"] == {"state": "aborted", "error": "watchdog"}
    assert rig.c.coord(1)["rotary"]["used_words"] == 0  # lookahead dropped with the motion
    assert rig.c.motor_status(1)[0] & (1 << 13)  # motor 1 not moving (desired velocity zero)


def test_a_tripped_card_refuses_resource_commands_but_can_be_read(rig):
    """TSRM p57: the tripped card does nothing until the power cycle — run / quit / abort /
    DEFINE ROT / variable writes are refused like the terminal; its state stays readable."""
    rig.rotary_setup()
    rig.c.load_lines(1, ["TM1000 X100", "X200", "X300"])
    rig.ok("&1 R")
    oversized_plc0(rig)
    rig.run_for(2.5)
    n = rig.c.log.last_seq
    for act in (lambda: rig.c.run(1), lambda: rig.c.quit(1), lambda: rig.c.abort(1),
                lambda: rig.c.define_rotary(2, 10), lambda: rig.c.delete_rotary(1),
                lambda: rig.c.set_variable("P1", 1)):
        with pytest.raises(Halted):
            act()
    rig.run_for(1.0)
    assert rig.c.log.last_seq == n  # nothing moved
    assert rig.c.coord(1)["program"]["state"] == "aborted"
    assert rig.c.get_variable("I40") == 0


def test_the_trip_turns_off_every_output_that_is_on_and_leaves_the_off_ones(rig):
    """TSRM p57: outputs go off at the trip — negative values too; an M-variable already 0
    gets no write (no ``mvar`` event)."""
    for text in ("M7=-3", "M8=0", "M9=2"):
        rig.ok(text)
    oversized_plc0(rig)
    rig.run_for(2.5)
    trip_seq = rig.c.log.events("watchdog")[0].seq
    writes = [(e.fields["name"], e.fields["value"]) for e in rig.c.log.read(trip_seq).events
              if e.type == "mvar"]
    assert ("M7", 0) in writes and ("M9", 0) in writes
    assert not [w for w in writes if w[0] == "M8"]
    assert rig.c.get_variable("M7") == 0
