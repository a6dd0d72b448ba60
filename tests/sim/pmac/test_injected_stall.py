"""An injected stall (sim/faults.py): the background gets no processor time in a window, as
when foreground tasks take the whole processor (TUM p236-237). Host commands wait for the
first background cycle after it; a window longer than I40 servo cycles trips the watchdog."""

from __future__ import annotations


def test_a_command_sent_in_a_stall_is_answered_in_the_first_cycle_after_it(rig):
    k0 = rig.cyc(rig.cmd("I10").t_done)
    free = rig.cyc(rig.cmd("I10").t_done) - k0  # the idle card: the next servo cycle
    t0 = rig.c.now
    rig.c.background.stall(t0, t0 + 0.05)
    reply = rig.cmd("I10")
    assert reply.error is None
    end = rig.cyc(rig.c.scheduler.servo_at_or_after(t0 + 0.05))
    assert end <= rig.cyc(reply.t_done) <= end + free


def test_a_stall_in_the_future_leaves_the_card_answering_until_it_starts(rig):
    t0 = rig.c.now
    rig.c.background.stall(t0 + 0.1, t0 + 0.2)
    before = rig.cmd("I10")
    assert before.t_done < t0 + 0.01
    rig.run_for(0.12 - (rig.c.now - t0))
    during = rig.cmd("I10")
    assert during.t_done >= t0 + 0.2


def test_a_stall_longer_than_the_watchdog_time_trips_it(make_rig):
    rig = make_rig(i40=300)  # 300 servo cycles ≈ 133 ms
    t0 = rig.c.now
    rig.c.background.stall(t0, t0 + 0.5)
    rig.run_for(0.6)
    (trip,) = rig.events("watchdog")
    assert trip[0] - rig.cyc(rig.c.scheduler.servo_at_or_after(t0)) <= 301
    assert trip[0] * rig.period < t0 + 0.5


def test_a_stall_shorter_than_the_watchdog_time_does_not_trip_it(make_rig):
    rig = make_rig(i40=300)
    t0 = rig.c.now
    rig.c.background.stall(t0, t0 + 0.1)
    rig.run_for(0.5)
    assert rig.events("watchdog") == []
    assert rig.cmd("I10").error is None


def test_a_stall_trips_the_watchdog_even_with_a_zero_housekeeping_cost(make_rig):
    """The watchdog is reloaded by background cycles that run (TUM p236-237): a background
    given no processor time reloads nothing, whatever its own cost is set to."""
    rig = make_rig(i40=300, cpu_housekeeping_us=0)
    t0 = rig.c.now
    rig.c.background.stall(t0, t0 + 0.5)
    rig.run_for(0.6)
    (trip,) = rig.events("watchdog")
    assert trip[0] - rig.cyc(rig.c.scheduler.servo_at_or_after(t0)) <= 301
