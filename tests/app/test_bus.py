"""The event bus: cursors read the ring by seq; no queue, gaps when they fall behind."""

from __future__ import annotations

import asyncio

import pytest
import simpy
from motionsim.app.bus import Cursor
from motionsim.sim.events import EventLog


def _log(capacity=100_000):
    return EventLog(simpy.Environment(), "c", capacity)


def test_read_returns_wire_messages_in_batches_and_advances():
    log = _log()
    for i in range(5):
        log.emit("tick", n=i)
    cur = Cursor(log, since=1, batch=3)
    assert [m["seq"] for m in cur.read()] == [2, 3, 4]
    assert cur.behind
    assert [m["seq"] for m in cur.read()] == [5]
    assert not cur.behind and cur.read() == []
    assert cur.read() == [] and cur.since == 5


def test_type_filter_skips_past_other_events():
    log = _log()
    log.emit("a")
    log.emit("b", x=1)
    log.emit("a")
    cur = Cursor(log, types={"b"})
    assert cur.read() == [{"seq": 2, "t": 0, "type": "b", "controller": "c", "x": 1}]
    assert cur.read() == [] and not cur.behind


def test_a_cursor_behind_the_ring_gets_one_gap_then_continues():
    log = _log(capacity=10)
    for i in range(25):
        log.emit("tick", n=i)
    cur = Cursor(log, since=3)
    msgs = cur.read()
    assert msgs[0] == {"type": "gap", "from": 4, "to": 15}
    assert [m["seq"] for m in msgs[1:]] == list(range(16, 26))


def test_wait_sleeps_until_the_next_emit_without_polling():
    async def main():
        log = _log()
        cur = Cursor(log)
        waiter = asyncio.create_task(cur.wait())
        await asyncio.sleep(0.01)
        assert not waiter.done()
        log.emit("tick")
        await asyncio.wait_for(waiter, 1)
        return cur.read()

    assert [m["seq"] for m in asyncio.run(main())] == [1]


def test_wait_returns_when_another_future_completes():
    async def main():
        cur = Cursor(_log())
        other = asyncio.get_running_loop().create_future()
        task = asyncio.create_task(cur.wait(other))
        other.set_result(None)
        await asyncio.wait_for(task, 1)

    asyncio.run(main())


def test_many_slow_cursors_hold_no_memory_of_their_own():
    log = _log(capacity=1000)
    cursors = [Cursor(log) for _ in range(100)]
    for i in range(5000):
        log.emit("tick", n=i)
    first = cursors[0].read()
    assert first[0] == {"type": "gap", "from": 1, "to": 4000}
    assert all(c.since == 0 for c in cursors[1:])


def test_negative_since_is_rejected():
    with pytest.raises(ValueError):
        Cursor(_log(), since=-1)


def test_a_cursor_without_since_delivers_the_log_from_its_first_event():
    """API.md: events with ``seq > since``; no ``since`` means from the start (seq 1)."""
    log = _log()
    for i in range(3):
        log.emit("tick", n=i)
    assert [m["seq"] for m in Cursor(log).read()] == [1, 2, 3]


def test_a_cursor_that_read_everything_is_not_behind_past_seq_256():
    """A caught-up cursor waits for the next event even with seqs beyond the small-int range
    (seq compared by value, not identity)."""

    async def main():
        log = _log()
        for i in range(300):
            log.emit("tick", n=i)
        cur = Cursor(log, since=250)
        while cur.read():
            pass
        assert cur.since == log.last_seq == 300 and not cur.behind
        waiter = asyncio.create_task(cur.wait())
        await asyncio.sleep(0.01)
        assert not waiter.done()
        log.emit("tick", n=300)
        await asyncio.wait_for(waiter, 1)
        return cur.read()

    assert [m["seq"] for m in asyncio.run(main())] == [301]


def test_read_text_is_json_of_read_and_shares_each_events_text_between_cursors():
    """Every subscriber of a log gets the same bytes as ``json.dumps`` of its messages (a gap
    included), and an event is encoded once for all of them (one string object)."""
    import json

    log = _log(capacity=10)
    for i in range(25):
        log.emit("tick", n=i, label=f"é{i}")
    a, b, plain = Cursor(log, since=3), Cursor(log, since=3), Cursor(log, since=3)
    texts_a, texts_b = a.read_text(), b.read_text()
    assert texts_a == [json.dumps(m) for m in plain.read()]
    assert texts_a[0] == json.dumps({"type": "gap", "from": 4, "to": 15})
    assert all(x is y for x, y in zip(texts_a[1:], texts_b[1:], strict=True))
    assert a.since == plain.since == 25
    other_id = Cursor(log, since=20, controller="renamed").read_text()
    assert [json.loads(t)["controller"] for t in other_id] == ["renamed"] * 5


def test_shared_texts_stay_right_far_beyond_what_is_kept():
    """A cursor far behind the newest events (their texts long pruned) still reads exactly
    the wire form of each event it is given."""
    import json

    from motionsim.app import bus

    log = _log(capacity=100_000)
    ahead, behind = Cursor(log), Cursor(log)
    for i in range(3 * bus.TEXTS_KEPT):
        log.emit("tick", n=i)
        if i % 500 == 0:
            while ahead.behind:
                ahead.read_text()
    got = []
    while behind.behind:
        got += behind.read_text()
    assert [json.loads(t)["n"] for t in got] == list(range(3 * bus.TEXTS_KEPT))


def test_shared_texts_are_the_newest_events_and_a_late_reader_leaves_them_alone(monkeypatch):
    """Memory stays bounded: the shared texts are those of the newest ``TEXTS_KEPT`` events
    (at most twice as many between prunes); a reader far behind encodes its own."""
    from motionsim.app import bus

    monkeypatch.setattr(bus, "TEXTS_KEPT", 8)
    log = _log()
    ahead = Cursor(log, batch=1)
    shared = bus._texts(log, "c")
    held = []
    for i in range(40):
        log.emit("tick", n=i)
        ahead.read_text()
        held.append(sorted(shared.by_seq))
    # 16 texts; the 17th prunes to the 8 newest (10..17); every 8 events again (19.., 28..)
    assert held[15] == list(range(1, 17))
    assert held[16] == list(range(10, 18))
    assert held[24] == list(range(10, 26))
    assert held[25] == list(range(19, 27))
    assert held[39] == list(range(28, 41))
    late = Cursor(log, since=3)  # 37 events behind
    before = dict(shared.by_seq)
    texts = []
    while late.behind:
        texts += late.read_text()
    assert len(texts) == 37
    assert shared.by_seq == before  # nothing of the late reader's was added, nothing pruned
    assert all(texts[k - 4] is before[k] for k in before)  # but it shared the newest ones


def test_wait_leaves_no_callback_on_the_other_futures():
    """Waiting once per event on a long-lived future (the route's disconnect watch) must not
    pile callbacks onto it."""
    async def main():
        log = _log()
        cur = Cursor(log)
        other = asyncio.get_running_loop().create_future()
        for i in range(50):
            task = asyncio.create_task(cur.wait(other))
            await asyncio.sleep(0)
            log.emit("tick", n=i)
            await asyncio.wait_for(task, 1)
            cur.read()
        left = len(other._callbacks or [])  # asyncio.Future's pending done-callbacks
        task = asyncio.create_task(cur.wait(other))
        await asyncio.sleep(0)
        other.set_result(None)  # the long-lived future completing still wakes a waiter
        await asyncio.wait_for(task, 1)
        return left

    assert asyncio.run(main()) == 0


def test_only_events_newer_than_the_window_are_shared(monkeypatch):
    """A first reader of 20 held events with a window of 8 shares the texts of seq 13..20:
    the 8 newest, not the one at the window's edge."""
    from motionsim.app import bus

    monkeypatch.setattr(bus, "TEXTS_KEPT", 8)
    log = _log()
    for i in range(20):
        log.emit("tick", n=i)
    cur = Cursor(log)
    while cur.behind:
        cur.read_text()
    assert sorted(bus._texts(log, "c").by_seq) == list(range(13, 21))


def test_the_shared_window_stays_bounded_at_its_real_scale(monkeypatch):
    """With a window past the small integers Python keeps once (here 300: pruned at 600
    texts), the texts held never exceed twice the window."""
    from motionsim.app import bus

    monkeypatch.setattr(bus, "TEXTS_KEPT", 300)
    log = _log()
    cur = Cursor(log, batch=1)
    sizes = []
    for i in range(2000):
        log.emit("tick", n=i)
        cur.read_text()
        sizes.append(len(bus._texts(log, "c").by_seq))
    assert max(sizes) == 600 and sizes[-1] < 600
    assert min(bus._texts(log, "c").by_seq) > 2000 - 600
