"""Registry and ControllerHandle: creation rules, terminal timing, apply at the current instant."""

from __future__ import annotations

import asyncio

import pytest
from motionsim.app.clock import RealtimeClock, VirtualClock
from motionsim.app.registry import Registry
from motionsim.sim.errors import Conflict, InvalidValue, NotFound

import tests.dummy_kind  # noqa: F401


def test_get_unknown_id_raises_not_found_naming_it():
    reg = Registry()
    with pytest.raises(NotFound, match="'x'"):
        reg.get("x")


def test_add_creates_a_controller_with_its_clock():
    reg = Registry()
    h = reg.add("dummy", "a", clock="virtual")
    assert (h.id, h.kind, type(h.clock)) == ("a", "dummy", VirtualClock)
    assert reg.get("a") is h and reg.ids() == ["a"]
    assert h.controller.log.capacity == 100_000


def test_add_bad_input_changes_nothing():
    reg = Registry()
    reg.add("dummy", "a", clock="virtual")
    with pytest.raises(Conflict):
        reg.add("dummy", "a")
    with pytest.raises(InvalidValue, match="unknown controller kind 'zz'"):
        reg.add("zz", "b")
    with pytest.raises(InvalidValue):
        reg.add("dummy", "b c")
    with pytest.raises(InvalidValue):
        reg.add("dummy", "b", config={"nope": 1})
    with pytest.raises(InvalidValue):
        reg.add("dummy", "b", clock="sometimes")  # type: ignore[arg-type]
    assert reg.ids() == ["a"]


def test_virtual_command_steps_to_the_reply_instant():
    async def main():
        h = Registry().add("dummy", "a", clock="virtual", config={"reply_delay_s": 0.002})
        reply = await h.command("ECHO x")
        return reply, h.controller.env.now

    reply, now = asyncio.run(main())
    assert (reply.done, reply.reply, reply.t_done) == (True, "x", pytest.approx(0.002))
    assert now == pytest.approx(0.002)


def test_virtual_command_gives_up_after_1s_simulated():
    async def main():
        h = Registry().add("dummy", "a", clock="virtual")
        reply = await h.command("SLOW")
        return reply, h.controller.env.now

    reply, now = asyncio.run(main())
    assert not reply.done
    assert now == pytest.approx(1.0)


def test_command_on_a_port_keeps_that_ports_state():
    async def main():
        h = Registry().add("dummy", "a", clock="virtual")
        tcp = h.open_port("tcp1")
        await h.command("ADDR 7", tcp)
        return (await h.command("ADDR ?", tcp)).reply, (await h.command("ADDR ?")).reply

    assert asyncio.run(main()) == ("7", "1")


def test_realtime_command_lands_at_the_wall_instant():
    async def main():
        reg = Registry()
        await reg.start()
        h = reg.add("dummy", "a", clock="realtime", config={"tick_s": 0})
        await asyncio.sleep(0.2)
        h.apply(h.controller.set_variable, "V1", 1.0)
        reply = await h.command("ECHO y")
        await reg.close()
        return h.controller.log.events("var")[0].t, reply

    t_var, reply = asyncio.run(main())
    assert 0.15 < t_var < 0.6
    assert reply.reply == "y"


def test_realtime_clock_starts_lazily_when_a_loop_runs():
    async def main():
        h = Registry().add("dummy", "a", clock="realtime")
        assert isinstance(h.clock, RealtimeClock) and not h.clock.running
        h.ensure_running()
        running = h.clock.running
        await h.close()
        return running

    assert asyncio.run(main()) is True


def test_to_dict_merges_status_under_id_kind_clock():
    h = Registry().add("dummy", "a", clock="virtual")
    assert h.to_dict() == {"ticks": 0, "id": "a", "kind": "dummy",
                           "clock": {"mode": "virtual", "factor": 1.0, "paused": False, "t": 0.0}}


def test_remove_forgets_the_controller():
    async def main():
        reg = Registry()
        reg.add("dummy", "a", clock="realtime")
        await reg.start()
        await reg.remove("a")
        with pytest.raises(NotFound):
            await reg.remove("a")
        return len(reg)

    assert asyncio.run(main()) == 0


def test_apply_from_another_thread_runs_on_the_controllers_loop():
    """A plain ``def`` FastAPI route runs in a worker thread; its mutation must not."""
    import threading

    async def main():
        h = Registry().add("dummy", "a", clock="realtime")
        h.ensure_running()
        loop_thread = threading.get_ident()
        ran_on = []

        def mutate(value):
            ran_on.append(threading.get_ident())
            h.controller.set_variable("V1", value)
            return value * 2

        result = await asyncio.to_thread(h.apply, mutate, 21.0)
        with pytest.raises(NotFound):
            await asyncio.to_thread(h.apply, h.controller.get_variable, "nope")
        await h.close()
        return loop_thread, ran_on, result, h.controller.get_variable("V1")

    loop_thread, ran_on, result, v1 = asyncio.run(main())
    assert ran_on == [loop_thread]
    assert (result, v1) == (42.0, 21.0)
