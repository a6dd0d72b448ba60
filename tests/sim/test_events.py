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


def test_the_wire_form_writes_simulated_time_to_the_nanosecond() -> None:
    """Issue 36 item 5 / API.md "Events": float noise of summed servo periods never reaches the
    JSON; the core's own ``t`` stays the instant SimPy scheduled."""
    env, log = make_log()
    for _ in range(12):  # twelve 100-us servo periods: 0.0012000000000000001 as a float sum
        env.run(until=env.now + 0.0001)
    assert env.now != 0.0012
    log.emit("breq", cs=1, level=True)
    env.run(until=env.now + 3.5e-10)  # half a nanosecond later rounds down ...
    log.emit("breq", cs=1, level=False)
    env.run(until=env.now + 3e-10)  # ... and this one up to the next nanosecond
    log.emit("breq", cs=1, level=True)
    first, second, third = log.events()
    assert first.t != 0.0012  # the core keeps the scheduled float
    assert [e.to_dict()["t"] for e in (first, second, third)] == [0.0012, 0.0012, 0.001200001]
    assert log.to_jsonl().splitlines()[0].startswith('{"seq":1,"t":0.0012,"type":"breq"')


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


def test_a_pattern_from_json_matches_by_value_type_and_fields() -> None:
    """A run-until pattern arrives as JSON (API.md): its strings and numbers are equal to the
    event's, not the same objects; every key must match, ``type`` against the event type."""
    import json

    _, log = make_log()
    log.emit("mvar", name="M1", value=100_000, words=3)
    (event,) = log.events()
    assert event.matches(json.loads('{"type": "mvar", "name": "M1", "value": 100000}'))
    assert event.matches(json.loads('{"words": 3, "value": 100000}'))
    assert event.matches({})
    for other in ("breq", "zzz", "mvaz", "a"):
        assert not event.matches({"type": other})
    assert not event.matches({"value": 99_999}) and not event.matches({"value": 100_001})
    assert not event.matches({"name": "M0"}) and not event.matches({"cs": 1})


def test_the_log_holds_the_newest_100000_events_by_default() -> None:
    """API.md: the log keeps at least the last 100 000 events."""
    env = simpy.Environment()
    log = EventLog(env, "c")
    for _ in range(100_001):
        log.emit("tick")
    assert log.first_seq == 2 and len(log) == 100_000


def test_capacity_is_at_least_one_event() -> None:
    import pytest

    with pytest.raises(ValueError):
        EventLog(simpy.Environment(), "c", 0)
    _, log = make_log(capacity=1)
    log.emit("a")
    log.emit("b")
    assert [e.type for e in log.events()] == ["b"] and len(log) == 1


def test_the_epoch_is_the_given_one_or_a_fresh_one_per_log() -> None:
    env = simpy.Environment()
    assert EventLog(env, "c", epoch="e-17").epoch == "e-17"
    a, b = EventLog(env, "c").epoch, EventLog(env, "c").epoch
    assert a and b and a != b and isinstance(a, str)


def test_seq_range_of_a_short_log_starts_at_one() -> None:
    _, log = make_log()
    assert log.first_seq == 1 and log.last_seq == 0 and len(log) == 0
    for _ in range(3):
        log.emit("tick")
    assert log.first_seq == 1 and len(log) == 3


def test_resume_keeps_a_position_of_this_log_and_resets_any_other() -> None:
    """API.md: a stale epoch or a since beyond the newest seq reads again from the start."""
    import json

    _, log = make_log()
    for _ in range(300):
        log.emit("tick")
    same = json.loads(json.dumps(log.epoch))  # equal, another object (as from a query)
    assert log.resume(0) == (0, None)
    assert log.resume(300, same) == (300, None)
    assert log.resume(299) == (299, None)
    since, reset = log.resume(301)
    assert since == 0 and (reset.reason, reset.since, reset.last_seq) == ("since_beyond_end",
                                                                           301, 300)
    for other in ("", "0", "~", log.epoch + "x"):
        since, reset = log.resume(5, other)
        assert since == 0 and reset.reason == "stale_epoch" and reset.epoch == log.epoch


def test_read_without_since_starts_at_seq_1_and_a_gap_is_exact() -> None:
    _, log = make_log(capacity=10)
    for i in range(25):
        log.emit("tick", n=i)
    assert [e.seq for e in log.read().events] == list(range(16, 26))
    one = log.read(14)
    assert (one.gap.from_seq, one.gap.to_seq) == (15, 15)
    assert log.read(15).gap is None and [e.seq for e in log.read(15).events][0] == 16
    assert len(log) == 10
    _, short = make_log()
    short.emit("a")
    short.emit("b")
    assert [e.seq for e in short.read().events] == [1, 2] and short.read().gap is None


def test_a_read_limit_beyond_256_is_honoured() -> None:
    _, log = make_log()
    for _ in range(400):
        log.emit("tick")
    res = log.read(0, None, 300)
    assert len(res.events) == 300 and res.next == 300


def test_events_of_the_given_types_only() -> None:
    _, log = make_log()
    for t in ("a", "b", "a", "c"):
        log.emit(t)
    assert [e.seq for e in log.events("a")] == [1, 3]
    assert [e.seq for e in log.events("b", "c")] == [2, 4]


def test_jsonl_lines_are_the_wire_form_in_its_key_order() -> None:
    """API.md's event shape ``{"seq", "t", "type", "controller", ...fields}``, keys in that
    order (fields in emit order), one compact JSON object per line; the controller id is the
    log's unless another is given."""
    _, log = make_log()
    log.emit("mvar", value=1, name="M1")
    line = '{"seq":1,"t":0,"type":"mvar","controller":"c","value":1,"name":"M1"}\n'
    assert log.to_jsonl() == line
    assert '"controller":"x"' in log.to_jsonl("x")


def test_the_ring_grows_with_the_events_and_then_wraps():
    """An idle log holds nothing (issue 35: 100 000 empty slots per controller were most of an
    idle controller's memory); once full it keeps the newest ``capacity`` events."""
    import sys

    env = simpy.Environment()
    log = EventLog(env, capacity=3)
    assert sys.getsizeof(log._ring) < 100 and log.read().events == []
    for k in range(1, 6):
        log.emit("x", k=k)
        held = [e.fields["k"] for e in log.read().events]
        assert held == list(range(max(1, k - 2), k + 1))
    result = log.read(since=0)
    assert result.gap is not None and (result.gap.from_seq, result.gap.to_seq) == (1, 2)


def test_emit_row_is_emit_of_the_same_fields():
    """``emit_row(type, keys, values)`` (the per-line events, stored as two tuples) is
    ``emit(type, **dict(zip(keys, values)))``: the same events read back, in the ring and
    through a wrap, the same JSON lines byte for byte, the same event to a listener, and
    waiters woken alike. The differential pin of the one rule of an event's shape."""
    rows = [
        ("line_loaded", ("cs", "n", "text", "words", "lines_ahead"), (1, 7, "X1 Y2", 2, 3)),
        ("breq", ("cs", "level"), (1, False)),
        ("move_end", ("cs", "n"), (2, 41)),
        ("reset", (), ()),
    ]
    logs, heard, woken = [], [], []
    for use_row in (False, True):
        env = simpy.Environment()
        log = EventLog(env, "c", capacity=5, epoch="e")
        got: list = []
        log.listen(got.append)
        wakes: list = []
        log.wake_on_next(lambda w=wakes, lg=log: w.append(lg.last_seq))
        for k in range(3):  # 12 events through a ring of 5
            env.run(until=0.001 * (k + 1))
            for type_, keys, values in rows:
                if use_row:
                    log.emit_row(type_, keys, values)
                else:
                    log.emit(type_, **dict(zip(keys, values, strict=True)))
        logs.append(log)
        heard.append(got)
        woken.append(wakes)
    plain, compact = logs
    assert compact.to_jsonl() == plain.to_jsonl()
    assert compact.events() == plain.events() and len(compact.events()) == 5
    some = {"since": 8, "types": ["breq", "reset"]}
    assert compact.read(**some) == plain.read(**some)
    assert heard[1] == heard[0] and len(heard[0]) == 12
    assert woken[1] == woken[0] == [1]
