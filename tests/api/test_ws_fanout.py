"""The WebSocket fan-out writes each caught-up subscriber the messages its own task would send.

API.md, Events: the stream is one JSON event per message (``batch=true``: an array per read),
in ``seq`` order, a ``gap`` when the ring moved past the reader; a slow client only falls
behind. The fan-out (:mod:`motionsim.api.ws_fanout`) frames once and writes to many: these
tests pin its frames to :meth:`Cursor.read_text` (the task's rule) and its hand-backs to the
cases the task must serve itself. No wall clock: the loop is only turned.
"""

from __future__ import annotations

import asyncio

import simpy
from motionsim.api.ws_fanout import BATCH, fanout_of, stream_live
from motionsim.api.ws_protocol import text_frame
from motionsim.app.bus import Cursor
from motionsim.sim.events import EventLog
from websockets.protocol import State
from websockets.server import ServerProtocol


def _texts(data: bytes) -> list[str]:
    """The text messages in ``data``: unmasked, final text frames (what a server sends)."""
    out, i = [], 0
    while i < len(data):
        assert data[i] == 0x81, data[i:i + 2]  # FIN + text
        n, i = data[i + 1], i + 2
        assert not n & 0x80  # a server never masks (RFC 6455 5.1)
        if n == 126:
            n, i = int.from_bytes(data[i:i + 2], "big"), i + 2
        elif n == 127:
            n, i = int.from_bytes(data[i:i + 8], "big"), i + 8
        out.append(data[i:i + n].decode())
        i += n
    return out


class Sink:
    """A subscriber's transport: records what is written; ``open`` False refuses (paused)."""

    def __init__(self) -> None:
        self.writes: list[bytes] = []
        self.open = True

    def __call__(self, data: bytes) -> bool:
        if not self.open:
            return False
        self.writes.append(data)
        return True

    def messages(self) -> list[str]:
        return [t for data in self.writes for t in _texts(data)]


def _log(capacity: int = 100_000) -> EventLog:
    return EventLog(simpy.Environment(), "c", capacity)


async def _turns(n: int = 5) -> None:
    for _ in range(n):
        await asyncio.sleep(0)


def test_a_text_frame_is_what_the_servers_protocol_sends_for_the_text():
    for text in ("{}", "x" * 125, "é" * 100, "y" * 70_000, '{"seq": 1, "t": 0.0012}'):
        proto = ServerProtocol(state=State.OPEN)
        proto.send_text(text.encode())
        assert text_frame(text) == b"".join(proto.data_to_send())
        assert _texts(text_frame(text)) == [text]


def test_live_subscribers_get_the_cursors_messages_one_frame_each_in_order():
    async def main():
        log = _log()
        log.emit("tick", n=0)
        ref = Cursor(log, since=1, controller="c")  # the task's rule, read at the end
        plain, typed, batched = Sink(), Sink(), Sink()
        subs = [(Cursor(log, since=1, controller="c"), plain, False),
                (Cursor(log, since=1, types={"var"}, controller="c"), typed, False),
                (Cursor(log, since=1, controller="c"), batched, True)]
        tasks = [asyncio.create_task(stream_live(c, w, b)) for c, w, b in subs]
        await _turns()
        for k in range(1, 6):
            log.emit("tick", n=k)
            if k % 2:
                log.emit("var", name="V1", value=k)
            await _turns()
        assert not any(t.done() for t in tasks)
        for t in tasks:
            t.cancel()
        await asyncio.gather(*tasks, return_exceptions=True)
        return ref.read_text(), plain, typed, batched, [c.since for c, _, _ in subs]

    ref, plain, typed, batched, sinces = asyncio.run(main())
    assert plain.messages() == ref  # one message per event, byte for byte
    assert typed.messages() == [t for t in ref if '"type": "var"' in t]
    # each emit was flushed on its own: one array per flush, events of one step together
    assert batched.messages() == ["[" + ", ".join(ref[i:j]) + "]"
                                  for i, j in ((0, 2), (2, 3), (3, 5), (5, 6), (6, 8))]
    assert sinces == [9, 9, 9]


def test_subscribers_reading_the_same_events_share_one_framing():
    async def main():
        log = _log()
        sinks = [Sink() for _ in range(3)]
        tasks = [asyncio.create_task(stream_live(Cursor(log), s, False)) for s in sinks]
        await _turns()
        log.emit("tick", n=1)
        await _turns()
        for t in tasks:
            t.cancel()
        await asyncio.gather(*tasks, return_exceptions=True)
        return sinks

    a, b, c = asyncio.run(main())
    assert a.writes[0] is b.writes[0] is c.writes[0]


def test_a_paused_transport_gets_nothing_and_its_task_takes_the_stream_back():
    async def main():
        log = _log()
        slow, fast = Sink(), Sink()
        slow_cursor = Cursor(log)
        slow_task = asyncio.create_task(stream_live(slow_cursor, slow, False))
        fast_task = asyncio.create_task(stream_live(Cursor(log), fast, False))
        await _turns()
        log.emit("tick", n=1)
        await _turns()
        slow.open = False  # flow control paused it: the buffer is over the high-water mark
        log.emit("tick", n=2)
        await _turns()
        handed_back = slow_task.done()
        log.emit("tick", n=3)
        await _turns()
        fast_task.cancel()
        await asyncio.gather(fast_task, return_exceptions=True)
        return handed_back, slow, fast, slow_cursor.since, fanout_of(log).live

    handed_back, slow, fast, slow_since, live = asyncio.run(main())
    assert handed_back
    assert [len(slow.messages()), len(fast.messages())] == [1, 3]
    assert slow_since == 1  # the task continues after the last event written, no loss
    assert not live


def test_a_burst_longer_than_a_batch_and_a_gap_go_back_to_the_task():
    async def main():
        log = _log()
        burst_cursor = Cursor(log)
        burst = asyncio.create_task(stream_live(burst_cursor, Sink(), False))
        await _turns()
        for k in range(BATCH + 1):  # one simulation slice emitting more than a batch
            log.emit("tick", n=k)
        await _turns()
        small = _log(capacity=10)
        gap_cursor = Cursor(small)
        gap = asyncio.create_task(stream_live(gap_cursor, Sink(), False))
        await _turns()
        for k in range(11):  # the ring moves past the cursor within a batch
            small.emit("tick", n=k)
        await _turns()
        return burst.done(), burst_cursor.since, gap.done(), gap_cursor.behind

    burst_back, burst_since, gap_back, gap_behind = asyncio.run(main())
    assert burst_back and burst_since == 0
    assert gap_back and gap_behind


def test_the_client_leaving_ends_the_live_stream_and_unregisters_it():
    async def main():
        log = _log()
        left = asyncio.get_running_loop().create_future()
        sink = Sink()
        task = asyncio.create_task(stream_live(Cursor(log), sink, False, left))
        await _turns()
        left.set_result(None)
        await _turns()
        log.emit("tick", n=1)
        await _turns()
        return task.done(), sink.writes, fanout_of(log).live

    done, writes, live = asyncio.run(main())
    assert done and writes == [] and not live
