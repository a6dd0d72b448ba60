"""What the rest of the core relies on from SimPy's queue (sim/simpy_adapter.py).

Servo instants are ``k * period`` exactly; at one instant the servo interrupt's URGENT events
run before NORMAL ones (the Trio servo pre-empts BASIC), each priority in the order pushed.
"""

import simpy
from motionsim.sim.simpy_adapter import (
    NORMAL,
    URGENT,
    clear_pre_step,
    next_eid,
    nothing_due_by,
    pre_step,
    push_at,
    set_now,
    step_due,
    triggered_at,
    urgent_at,
    wake_at,
)


def test_events_run_at_the_exact_instant_urgent_first_then_in_push_order():
    env = simpy.Environment()
    period = 0.000442700004577637  # an I10-derived servo period that does not round-trip
    t = 7 * period
    seen: list[tuple[str, float]] = []
    wake_at(env, t, lambda ev: seen.append(("normal-1", env.now)))
    wake_at(env, t, lambda ev: seen.append(("normal-2", env.now)))
    triggered_at(env, t, lambda ev: seen.append(("urgent", env.now)), URGENT)
    env.run()
    assert [name for name, _ in seen] == ["urgent", "normal-1", "normal-2"]
    assert all(now == t for _, now in seen)  # not now + (t - now)


def test_a_processed_wake_is_reused_and_a_cancelled_one_is_not():
    env = simpy.Environment()
    calls: list[float] = []
    first = wake_at(env, 1.0, lambda ev: calls.append(env.now))
    env.run()
    again = wake_at(env, 2.0, lambda ev: calls.append(env.now), first)
    assert again is first
    queued = wake_at(env, 3.0, lambda ev: calls.append(env.now))
    queued.callbacks.clear()  # cancelled while still on the queue
    other = wake_at(env, 4.0, lambda ev: calls.append(env.now), queued)
    assert other is not queued
    env.run()
    assert calls == [1.0, 2.0, 4.0]


def test_push_at_places_a_triggered_event_on_the_queue():
    env = simpy.Environment()
    ev = simpy.Event(env)
    ev._ok, ev._value = True, "x"
    got: list[object] = []
    ev.callbacks.append(lambda e: got.append((env.now, e.value)))
    push_at(env, 0.25, ev)
    env.run()
    assert got == [(0.25, "x")]


def test_pre_step_sees_each_events_queue_key_before_it_runs_until_cleared():
    """What data gathering relies on: the hook gets the key of the event about to run
    (``env.run`` and ``env.step`` both), may move the clock forward to an instant before it,
    and a tie-break number taken in between orders after the events already queued."""
    env = simpy.Environment()
    seen: list[tuple[str, object]] = []
    wake_at(env, 1.0, lambda ev: seen.append(("a", env.now)))
    triggered_at(env, 1.0, lambda ev: seen.append(("u", env.now)))
    virtual: list[int] = []

    def hook(t: float, priority: int, eid: int) -> None:
        seen.append(("hook", (t, priority)))
        if not virtual:
            virtual.append(next_eid(env))
            assert virtual[0] > eid  # after everything queued so far
            set_now(env, 0.5)
            seen.append(("moved", env.now))

    pre_step(env, hook)
    env.step()
    env.run(until=2.0)
    clear_pre_step(env)
    wake_at(env, 3.0, lambda ev: seen.append(("b", env.now)))
    env.run()
    assert seen == [("hook", (1.0, URGENT)), ("moved", 0.5), ("u", 1.0),
                    ("hook", (1.0, NORMAL)), ("a", 1.0), ("hook", (2.0, URGENT)),
                    ("b", 3.0)]


def test_nothing_due_by_looks_at_the_first_queued_instant_whatever_its_priority():
    """``nothing_due_by(env, t)``: no event at or before ``t`` is queued, so one pushed at ``t``
    is the next processed (the Trio resumption inside the servo interrupt relies on it)."""
    env = simpy.Environment()
    assert nothing_due_by(env, 0.0)
    wake_at(env, 0.002, lambda ev: None)
    assert nothing_due_by(env, 0.001) and not nothing_due_by(env, 0.002)
    urgent_at(env, 0.001, lambda ev: None)  # URGENT at 1 ms: due by 1 ms
    assert not nothing_due_by(env, 0.001) and nothing_due_by(env, 0.0009)
    env.step()
    assert env.now == 0.001 and nothing_due_by(env, 0.001)


def test_step_due_processes_at_most_n_events_due_by_the_limit_and_counts_them():
    env = simpy.Environment()
    seen: list[float] = []
    for t in (1.0, 2.0, 2.0, 3.0):
        wake_at(env, t, lambda ev: seen.append(env.now))
    assert step_due(env, 2.0, 2) == 2  # n binds: the second event at 2.0 waits
    assert seen == [1.0, 2.0]
    assert step_due(env, 2.0, 10) == 1  # the limit binds: 3.0 is not due
    assert seen == [1.0, 2.0, 2.0] and env.peek() == 3.0
    assert step_due(env, 5.0, 0) == 0 and env.now == 2.0
    assert step_due(env, 5.0, 10) == 1 and step_due(env, 5.0, 10) == 0  # queue empty


def test_step_due_honours_a_pre_step_hook_installed_by_an_event_it_processes():
    env = simpy.Environment()
    keys: list[float] = []
    wake_at(env, 1.0, lambda ev: pre_step(env, lambda t, p, e: keys.append(t)))
    wake_at(env, 2.0, lambda ev: None)
    wake_at(env, 3.0, lambda ev: clear_pre_step(env))
    wake_at(env, 4.0, lambda ev: None)
    assert step_due(env, 10.0, 10) == 4
    assert keys == [2.0, 3.0]  # seen from the event after the one that installed it
