"""The host-paced clock: time moves while every holder waits, holds where one is due."""

from __future__ import annotations

import asyncio
import time

import pytest
import simpy
from motionsim.app.clock import RealtimeClock
from motionsim.app.host_paced import HostPacedClock
from motionsim.sim.errors import Conflict, InvalidValue
from motionsim.sim.events import EventLog


def _ticker(env, log, period=0.1):
    k = 0
    while True:
        k += 1
        yield env.timeout(k * period - env.now)
        log.emit("tick", k=k)


def _clock(reaction_s=0.0):
    env = simpy.Environment()
    log = EventLog(env, "c")
    env.process(_ticker(env, log))
    return env, log, HostPacedClock(env, log=log, reaction_s=reaction_s)


def test_time_stands_still_while_a_registered_holder_acts():
    async def main():
        env, log, clock = _clock()
        clock.start()
        clock.hold("host")
        out = await clock.wait("main", None, 1.0, wall_timeout_s=0.2)
        t_held = env.now
        await clock.stop()
        return out, t_held, clock.held_by()

    (event, outcome), t_held, held_by = asyncio.run(main())
    assert (event, outcome, t_held) == (None, "wall_timeout", 0.0)


def test_a_holder_acts_reaction_s_after_its_event_and_time_holds_there():
    async def main():
        env, log, clock = _clock(reaction_s=0.025)
        clock.start()
        clock.hold("main")
        host = asyncio.ensure_future(clock.wait("host", {"type": "tick", "k": 3}, 10.0))
        main = asyncio.ensure_future(clock.wait("main", None, 1.0))
        event, outcome = await host
        await asyncio.sleep(0.05)           # the host "thinks" in wall time: nothing moves
        t_acting, ticks = env.now, [e["k"] for e in log.events()]
        await clock.wait("host", {"type": "tick", "k": 99}, 0.2)  # hand time back 0.2 s
        t_next = env.now
        clock.release("host")               # time no longer waits for it: main's turn
        await main
        await clock.stop()
        return event, outcome, t_acting, ticks, t_next, main.result()

    event, outcome, t_acting, ticks, t_next, main_out = asyncio.run(main())
    assert (event["k"], outcome) == (3, "matched")
    assert t_acting == pytest.approx(0.325)  # tick 3 at 0.3 s + 25 ms reaction
    assert ticks == [1, 2, 3]
    assert t_next == pytest.approx(0.525)
    assert main_out == (None, "timeout")  # main reached its deadline (1 s)


def test_releasing_a_holder_ends_its_wait_and_later_waits_return_released():
    async def main():
        env, log, clock = _clock()
        clock.start()
        clock.hold("main")
        wait = asyncio.ensure_future(clock.wait("host", {"type": "never"}, 10.0))
        await asyncio.sleep(0.01)
        clock.release("host")
        first = await wait
        again = await clock.wait("host", {"type": "never"}, 10.0)
        clock.hold("host")                  # registering again makes it a holder again
        state = clock.holders["host"].state
        await clock.stop()
        return first, again, state, env.now

    first, again, state, t = asyncio.run(main())
    assert first == (None, "released") and again == (None, "released")
    assert state == "acting" and t == 0.0   # main acted all along: time never moved


def test_holders_due_at_the_same_instant_act_one_at_a_time_in_a_fixed_order():
    """Two holders due at t = 0.3: "z" by its event (tick 3), waiting since t = 0; "a" by its
    deadline, waiting since t = 0.1. The one waiting since the earlier instant acts first,
    whatever order the calls were made in, and the other acts at the same instant only once
    the first waits again; equal instants would then go by name."""
    async def main(order):
        env, log, clock = _clock()
        clock.start()
        for name in order:
            clock.hold(name)
        turns: list[tuple[str, float, str]] = []

        async def host(name):
            if name == "a":
                await clock.wait(name, None, 0.1)
                event, outcome = await clock.wait(name, None, 0.2)
            else:
                event, outcome = await clock.wait(name, {"type": "tick", "k": 3}, 10.0)
            turns.append((name, round(env.now, 9), outcome))
            log.emit("acted", by=name)      # what it does lands at that instant
            await clock.wait(name, None, 0.05)
            clock.release(name)

        await asyncio.gather(*(host(n) for n in order))
        await clock.stop()
        return turns, [e["by"] for e in log.events() if e.type == "acted"]

    one = asyncio.run(main("az"))
    two = asyncio.run(main("za"))
    assert one == two
    assert one == ([("z", 0.3, "matched"), ("a", 0.3, "timeout")], ["z", "a"])


def test_bad_reaction_and_holder_names_are_refused():
    env = simpy.Environment()
    log = EventLog(env, "c")
    for bad in (-1, 61, float("nan")):
        with pytest.raises(InvalidValue):
            HostPacedClock(env, log=log, reaction_s=bad)
    clock = HostPacedClock(env, log=log)
    with pytest.raises(InvalidValue):
        clock.hold("no spaces")

    async def twice():
        clock.start()
        clock.hold("other")
        first = asyncio.ensure_future(clock.wait("h", None, 1.0))
        await asyncio.sleep(0)
        try:
            await clock.wait("h", None, 1.0)
        finally:
            first.cancel()
            await clock.stop()

    with pytest.raises(Conflict):
        asyncio.run(twice())


def test_realtime_clock_that_cannot_keep_up_reports_lag_and_slips_instead_of_freezing():
    """Each event costs 2 ms of CPU for 0.1 ms simulated: at factor 1 the clock falls behind.
    It reports ``behind`` with a ``clock_lag`` event, keeps its lag under ``max_lag_s`` by
    slipping, and the loop stays responsive (a 10 ms sleeper is served on time)."""
    env = simpy.Environment()
    log = EventLog(env, "c")

    def heavy():
        while True:
            yield env.timeout(0.0001)
            end = time.perf_counter() + 0.002
            while time.perf_counter() < end:
                pass

    env.process(heavy())

    async def main():
        clock = RealtimeClock(env, 1.0, log=log, max_lag_s=0.2, lag_report_s=0.05)
        clock.start()
        worst = 0.0
        for _ in range(60):
            t0 = time.monotonic()
            await asyncio.sleep(0.01)
            worst = max(worst, time.monotonic() - t0)
        state = clock.to_dict()
        await clock.stop()
        return state, worst

    state, worst = asyncio.run(main())
    assert state["behind"] is True and state["slipped_s"] > 0
    assert state["lag_s"] <= 0.2 + 0.01
    lags = [e for e in log.events() if e.type == "clock_lag"]
    assert lags and lags[0]["behind"] is True
    # never frozen: with 2000-event slices (the old clock) one slice alone took 4 s
    assert worst < 1.0
