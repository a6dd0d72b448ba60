"""The first RTI after an instant has one home, ``scheduler.first_rti_after`` (TUM p236: move
planning at real-time interrupts, every I8+1 servo cycles): the scheduler and the start of a
move (the coordinate system's per-line path, with I8+1 cached) both call it. Pinned here
against the servo clock's own cycle rule: the first cycle strictly after ``t``, rounded up to
a multiple of I8+1."""

from __future__ import annotations

import math

import simpy
from hypothesis import given
from hypothesis import strategies as st
from motionsim.sim.pmac.tasks.scheduler import Scheduler, first_rti_after, servo_at_or_after
from motionsim.sim.timing import ServoClock, pmac_servo_period_s

PERIODS = [pmac_servo_period_s(i10) for i10 in (3_713_707, 1_856_853, 7_427_414, 838_860)]


def by_the_clock(clock: ServoClock, t: float, m: int) -> float:
    k = clock.after(t)
    return clock.t(math.ceil(k / m) * m)


@given(
    period=st.sampled_from(PERIODS),
    m=st.integers(1, 16),
    k=st.integers(0, 10**7),
    offset=st.sampled_from([0.0, 1e-12, -1e-12, 0.3, 0.999, 0.5]),
)
def test_first_rti_after_is_the_clock_rule(period, m, k, offset):
    clock = ServoClock(period)
    t = (k + offset) * period  # on a cycle, a rounding step either side, between cycles
    got = first_rti_after(t, period, m)
    assert got == by_the_clock(clock, t, m)
    assert got > t or math.isclose(got, t)  # strictly after, to the clock's tolerance
    assert round(got / period) % m == 0


@given(period=st.sampled_from(PERIODS), i8=st.integers(0, 15), t=st.floats(0.0, 1e4))
def test_the_scheduler_answers_the_same(period, i8, t):
    sched = Scheduler(simpy.Environment(), period, lambda: i8 + 1)
    assert sched.next_rti_after(t) == first_rti_after(t, period, i8 + 1)


def test_an_instant_on_an_rti_gives_the_next_one():
    period = PERIODS[0]
    t = 6 * period  # an RTI with I8 = 2
    assert first_rti_after(t, period, 3) == 9 * period


@given(
    period=st.sampled_from(PERIODS),
    k=st.integers(0, 10**7),
    offset=st.sampled_from([0.0, 1e-12, -1e-12, 0.3, 0.999, 0.5]),
)
def test_servo_rounding_is_the_clock_rule(period, k, offset):
    """A blend's hand-off is rounded up to a servo cycle by ``servo_at_or_after``, the
    scheduler's rounding, which is the clock's."""
    clock = ServoClock(period)
    t = (k + offset) * period
    assert servo_at_or_after(t, period) == clock.t(clock.at_or_after(t))
    sched = Scheduler(simpy.Environment(), period, lambda: 3)
    assert sched.servo_at_or_after(t) == servo_at_or_after(t, period)
