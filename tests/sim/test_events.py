"""The event log: seq from 1 without holes, simulated timestamps, bounded ring with gaps."""

import simpy
from motionsim.sim.events import EventLog


def make_log(capacity: int = 100_000) -> tuple[simpy.Environment, EventLog]:
    env = simpy.Environment()
    return env, EventLog(env, "c", capacity)


def test_seq_starts_at_one_and_events_carry_simulated_time() -> None:
    env, log = make_log()
    log.emit("breq", cs=1, level=True)
    env.run(until=0.25)
    log.emit("breq", cs=1, level=False)
    events = log.events()
    assert [(e.seq, e.t, e.type, dict(e.fields)) for e in events] == [
        (1, 0, "breq", {"cs": 1, "level": True}),
        (2, 0.25, "breq", {"cs": 1, "level": False}),
    ]
    assert events[1].to_dict("c") == {
        "seq": 2, "t": 0.25, "type": "breq", "controller": "c", "cs": 1, "level": False,
    }


def test_read_since_filters_types_and_reports_next() -> None:
    _, log = make_log()
    for i in range(5):
        log.emit("a" if i % 2 else "b", i=i)
    res = log.read(since=1, types=["a"])
    assert [e.seq for e in res.events] == [2, 4]
    assert res.next == 5 and res.gap is None
    res = log.read(since=0, limit=2)
    assert [e.seq for e in res.events] == [1, 2] and res.next == 2


def test_ring_drops_oldest_and_reports_gap() -> None:
    _, log = make_log(capacity=3)
    for i in range(7):
        log.emit("x", i=i)
    assert log.first_seq == 5 and log.last_seq == 7 and len(log) == 3
    res = log.read(since=2)
    assert res.gap is not None and (res.gap.from_seq, res.gap.to_seq) == (3, 4)
    assert [e.seq for e in res.events] == [5, 6, 7]
    assert log.read(since=4).gap is None


def test_listeners_and_one_shot_wakers() -> None:
    _, log = make_log()
    seen: list[int] = []
    woken: list[int] = []
    stop = log.listen(lambda e: seen.append(e.seq))
    log.wake_on_next(lambda: woken.append(log.last_seq))
    log.emit("x")
    log.emit("x")
    stop()
    log.emit("x")
    assert seen == [1, 2] and woken == [1]


def test_match_pattern_and_jsonl_are_deterministic() -> None:
    def run() -> str:
        env, log = make_log()
        for k in range(3):
            if k:
                env.run(until=k * 0.000442)
            log.emit("move_start", cs=1, n=k + 1)
        assert log.events()[1].matches({"type": "move_start", "n": 2})
        assert not log.events()[1].matches({"type": "move_start", "n": 3})
        return log.to_jsonl()

    assert run() == run()
