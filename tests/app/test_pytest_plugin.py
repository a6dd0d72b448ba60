"""The ``motionsim`` pytest fixture, as a host author uses it (real server on 127.0.0.1)."""

from __future__ import annotations

import json

import pytest
from motionsim.app.client import MotionSimHTTPError
from motionsim.app.settings import Settings

import tests.dummy_kind  # noqa: F401


@pytest.fixture
def motionsim_settings():
    return Settings(clock={"mode": "virtual"}, pmac_port=0, trio_port=0,
                    controllers=[{"id": "d", "kind": "dummy"}])


def test_the_fixture_serves_a_virtual_clock_on_a_free_port(motionsim):
    assert motionsim.url.startswith("http://127.0.0.1:")
    assert motionsim.health()
    assert [c["id"] for c in motionsim.controllers()] == ["d"]
    assert motionsim.clock("d").mode == "virtual"
    assert motionsim.advance("d", 0.02).t == pytest.approx(0.02)
    assert [e["n"] for e in motionsim.all_events("d", types=["tick"])] == [1, 2]


def test_errors_are_raised_with_their_code(motionsim):
    with pytest.raises(MotionSimHTTPError) as exc:
        motionsim.controller("nope")
    assert (exc.value.status, exc.value.code) == (404, "not_found")
    with pytest.raises(MotionSimHTTPError) as exc:
        motionsim.advance("d", -1)
    assert (exc.value.status, exc.value.code, exc.value.body["field"]) == (
        422, "validation_error", "seconds")


def test_websocket_resume_over_a_real_socket_has_no_gaps_or_duplicates(motionsim):
    motionsim.advance("d", 0.05)
    with motionsim.subscribe("d", since=0, timeout=5) as events:
        first = [next(events) for _ in range(3)]
    motionsim.advance("d", 0.05)
    with motionsim.subscribe("d", since=first[-1]["seq"], timeout=5) as events:
        rest = [next(events) for _ in range(7)]
        motionsim.advance("d", 0.01)
        rest.append(next(events))
    assert [e["seq"] for e in first + rest] == list(range(1, 12))


def test_a_subscription_knows_the_log_epoch_and_is_told_of_a_reset(motionsim):
    motionsim.advance("d", 0.03)
    epoch = motionsim.events("d").epoch
    with motionsim.subscribe("d", since=0, timeout=5) as events:
        assert next(events)["seq"] == 1  # the epoch message is not yielded as an event
        assert (events.epoch, events.reset) == (epoch, None)
    with motionsim.subscribe("d", since=3, epoch="0123456789abcdef", timeout=5) as events:
        assert next(events)["seq"] == 1
        assert events.reset["reason"] == "stale_epoch"


def test_each_test_gets_a_fresh_service(motionsim):
    assert motionsim.clock("d").t == 0.0
    assert motionsim.all_events("d") == []


def test_protocol_ports_are_reported_when_enabled(pytester):
    """A host author's conftest turning the listeners on ('auto' ports) through the fixture."""
    pytester.makeconftest("""
        import asyncio, pytest
        import sys, types
        from motionsim.app import listeners as L
        from motionsim.app.settings import Settings
        import tests.dummy_kind

        @pytest.fixture(autouse=True)
        def fake_adapter(monkeypatch):
            mod = types.ModuleType("fake_srv")
            async def serve(handle, host, port, **kw):
                return await asyncio.start_server(lambda r, w: w.close(), host, port)
            mod.serve = serve
            monkeypatch.setitem(sys.modules, "fake_srv", mod)
            monkeypatch.setattr(L, "PROTOCOLS", (L.Protocol("fake", "fake_srv", "serve", 0,
                                                            "pmac_port", "pmac_controller"),))

        @pytest.fixture
        def motionsim_settings():
            return Settings(clock={"mode": "virtual"}, pmac_port="auto",
                            controllers=[{"id": "pmac", "kind": "dummy"}])
    """)
    pytester.makepyfile("""
        import socket
        def test_ports(motionsim):
            port = motionsim.ports["fake"]
            socket.create_connection(("127.0.0.1", port), timeout=5).close()
    """)
    result = pytester.runpytest_inprocess("-p", "no:cacheprovider")
    result.assert_outcomes(passed=1)


def test_a_stuck_websocket_subscriber_later_gets_a_gap_and_catches_up(motionsim):
    """Over a real socket: a client that stops reading only falls behind in the ring (the
    server holds no queue for it); when it reads again it gets a gap, then the newest events,
    in order, with no duplicates. The advance runs in slices while the server keeps sending,
    so the reader may be overrun more than once: every event is either delivered or inside
    exactly one gap."""
    from websockets.sync.client import connect

    url = motionsim.url.replace("http", "ws") + "/controllers/d/events"
    with connect(url, compression=None, proxy=None, max_queue=4) as ws:
        motionsim.advance("d", 4000.0)  # 400 000 ticks, four times the 100 000-event ring
        last = motionsim.controller("d")["ticks"]
        seqs, gaps = [], []
        while not seqs or seqs[-1] < last:
            msg = json.loads(ws.recv(timeout=20))
            if msg["type"] == "gap":
                gaps.append((msg["from"], msg["to"]))
            elif msg["type"] != "epoch":
                seqs.append(msg["seq"])
    assert gaps
    assert seqs == sorted(set(seqs))
    assert seqs[-1] == last == 400_000
    tail = list(range(gaps[-1][1] + 1, last + 1))  # after the last gap: every event, in order
    assert seqs[-len(tail):] == tail
    lost = [s for start, end in gaps for s in range(start, end + 1)]
    assert len(lost) == len(set(lost))
    assert not set(lost) & set(seqs)
    assert len(seqs) + len(lost) == last
