"""Clock drivers: virtual (advance, run-until, idle) and realtime (wall time × factor)."""

from __future__ import annotations

import asyncio
import math
import time
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager

import pytest
import simpy
from motionsim.app.clock import RealtimeClock, VirtualClock, make_clock, run_env_to
from motionsim.sim.errors import Conflict, InvalidValue
from motionsim.sim.events import EventLog


def _ticker(env, log, period, name="tick"):
    k = 0
    while True:
        k += 1
        yield env.timeout(k * period - env.now)
        log.emit(name, k=k)


def _setup(period=0.1):
    env = simpy.Environment()
    log = EventLog(env, "c")
    env.process(_ticker(env, log, period))
    return env, log


def test_advance_runs_events_up_to_and_at_the_target():
    env, log = _setup()
    VirtualClock(env).advance(0.3)
    assert env.now == pytest.approx(0.3)
    assert [e["k"] for e in log.events()] == [1, 2, 3]


def test_advance_zero_is_a_no_op():
    env, log = _setup()
    VirtualClock(env).advance(0)
    assert env.now == 0 and len(log) == 0


@pytest.mark.parametrize("bad", [-1, -1e-9, math.inf, math.nan, "x"])
def test_advance_rejects_negative_and_non_finite(bad):
    env, _ = _setup()
    with pytest.raises(InvalidValue) as exc:
        VirtualClock(env).advance(bad)
    assert exc.value.details["field"] == "seconds"
    assert env.now == 0


def test_advance_with_nothing_scheduled_still_moves_time():
    env = simpy.Environment()
    VirtualClock(env).advance(2.5)
    assert env.now == 2.5


def test_run_until_stops_at_the_matching_event_instant():
    env, log = _setup()
    ev = VirtualClock(env).run_until(log, {"type": "tick", "k": 4}, 10)
    assert (ev.seq, ev.t, ev["k"]) == (4, pytest.approx(0.4), 4)
    assert env.now == pytest.approx(0.4)


def test_run_until_accepts_a_predicate_and_times_out():
    env, log = _setup()
    assert VirtualClock(env).run_until(log, lambda e: e["k"] > 100, 1.0) is None
    assert env.now == pytest.approx(1.0)


def test_run_until_idle_returns_when_nothing_is_scheduled():
    env = simpy.Environment()

    def two_waits():
        yield env.timeout(1)
        yield env.timeout(1)

    env.process(two_waits())
    assert VirtualClock(env).run_until_idle() is True
    assert env.now == 2


def test_run_until_idle_is_bounded_for_a_perpetual_process():
    env, _ = _setup()
    assert VirtualClock(env).run_until_idle(max_s=0.55) is False
    assert env.now == pytest.approx(0.55)


def test_paused_virtual_clock_refuses_to_move():
    env, _ = _setup()
    clock = VirtualClock(env, paused=True)
    with pytest.raises(Conflict):
        clock.advance(1)


def test_run_env_to_in_slices():
    env, log = _setup(0.001)
    assert run_env_to(env, 1.0, max_steps=100) is False
    assert 90 <= len(log) <= 100
    while not run_env_to(env, 1.0, max_steps=100):
        pass
    assert env.now == 1.0 and len(log) == 1000


def test_make_clock_rejects_bad_mode_and_factor():
    env = simpy.Environment()
    with pytest.raises(InvalidValue):
        make_clock("fast", env)  # type: ignore[arg-type]
    with pytest.raises(InvalidValue) as exc:
        make_clock("realtime", env, factor=0)
    assert exc.value.details["field"] == "factor"


# -- realtime -------------------------------------------------------------------------------


@asynccontextmanager
async def _running(env: simpy.Environment, factor: float = 1.0) -> AsyncIterator[RealtimeClock]:
    """A started ``RealtimeClock`` on ``env``, stopped when the block ends."""
    clock = RealtimeClock(env, factor)
    clock.start()
    try:
        yield clock
    finally:
        await clock.stop()


async def _track(factor, wall_s, period):
    env, log = _setup(period)
    before = time.monotonic()
    async with _running(env, factor) as clock:
        await asyncio.sleep(wall_s)
        t_sim = clock.t
        elapsed = time.monotonic() - before
        events = log.events()
    return env, clock, events, elapsed, t_sim


@pytest.mark.parametrize("factor", [1.0, 10.0])
def test_realtime_clock_tracks_wall_time_times_factor(factor):
    """Only what a loaded machine cannot falsify: simulated time never runs ahead of wall ×
    factor (a stall only holds it back; how closely it follows is bench_spine.py's lateness),
    and every event due before the instant reached has run, once, at its own instant."""
    period = 0.01 * factor
    env, clock, events, elapsed, t_sim = asyncio.run(_track(factor, 0.5, period))
    assert 0 < t_sim <= elapsed * factor
    expected = int(t_sim / period + 1e-9)
    assert expected - 1 <= len(events) <= expected
    assert [e.t for e in events] == pytest.approx([(i + 1) * period
                                                   for i in range(len(events))])
    assert clock.lateness_s


def test_realtime_t_advances_with_nothing_scheduled():
    async def main():
        env = simpy.Environment()
        before = time.monotonic()
        async with _running(env, 4.0) as clock:
            await asyncio.sleep(0.2)
            t = clock.t
            elapsed = time.monotonic() - before
            clock.sync()
            now = env.now
        return t, now, elapsed

    t, now, elapsed = asyncio.run(main())
    assert 4.0 * 0.2 <= t <= 4.0 * elapsed  # nothing to compute: exactly the schedule
    assert now >= t


def test_realtime_pause_freezes_t_and_resume_continues():
    async def main():
        env, log = _setup(0.01)
        async with _running(env) as clock:
            await asyncio.sleep(0.1)
            clock.set(paused=True)
            t_pause, n_pause = clock.t, len(log)
            await asyncio.sleep(0.15)
            t_still, n_still = clock.t, len(log)
            resumed = time.monotonic()
            clock.set(paused=False)
            await asyncio.sleep(0.1)
            t_after = clock.t
            since = time.monotonic() - resumed
        return t_pause, n_pause, t_still, n_still, t_after, since

    t_pause, n_pause, t_still, n_still, t_after, since = asyncio.run(main())
    assert t_still == t_pause and n_still == n_pause
    assert t_pause < t_after <= t_pause + since  # it goes on from the paused instant


def test_realtime_factor_change_keeps_t_continuous():
    async def main():
        env = simpy.Environment()
        async with _running(env) as clock:
            await asyncio.sleep(0.1)
            before = clock.t
            changed = time.monotonic()
            clock.set(factor=10.0)
            just_after = clock.t
            await asyncio.sleep(0.1)
            later = clock.t
            since = time.monotonic() - changed
        return before, just_after, later, since

    before, just_after, later, since = asyncio.run(main())
    assert just_after == pytest.approx(before, abs=0.01)
    assert 10.0 * 0.1 <= later - just_after <= 10.0 * since  # ten times wall time from there


def test_realtime_wake_replans_for_an_event_scheduled_sooner():
    """A command schedules something sooner than the task's timer: it runs on time."""
    async def main():
        env = simpy.Environment()
        log = EventLog(env, "c")

        def later():
            yield env.timeout(0.05)
            log.emit("done")

        async with _running(env) as clock:
            await asyncio.sleep(0.05)  # nothing scheduled: the task sleeps on its future
            clock.sync()
            env.process(later())
            clock.wake()
            t_cmd = env.now
            await asyncio.sleep(0.2)
        return t_cmd, log.events("done")

    t_cmd, done = asyncio.run(main())
    assert len(done) == 1
    assert done[0].t == pytest.approx(t_cmd + 0.05)


def test_moving_time_leaves_nothing_due_behind():
    """After running to an instant, the next scheduled event is the ticker's, not a leftover."""
    env, _ = _setup(0.01)
    run_env_to(env, 0.0123)
    assert env.now == 0.0123
    assert env.peek() == pytest.approx(0.02)


def test_realtime_task_wakes_once_per_event_not_in_a_loop():
    async def main():
        env, log = _setup(0.01)
        async with _running(env) as clock:
            await asyncio.sleep(0.3)
        return len(log), len(clock.lateness_s)

    events, wakeups = asyncio.run(main())
    assert events >= 20
    assert wakeups <= 2 * events + 2
