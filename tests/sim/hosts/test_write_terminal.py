"""Rotary writers that write through the card's command line (``write_via="terminal"``, the
real PMAC core): ``OPEN ROT`` once, one program line per command line, each answered at the
end of a background cycle, one awaiting its answer at a time; a busy card slows the writes, a
tripped card silences them."""

from __future__ import annotations

import random

import pytest
from motionsim.sim.hosts import BreqInterruptHost, NaiveHost, PrPollingHost
from motionsim.sim.pmac import PmacController

MOVES = ["LINEAR", "ABS", "TA2", "TS0", "TM2", *(f"X{k}" for k in range(1, 401))]


def card(words: int = 6000, **config) -> PmacController:
    ctl = PmacController("pmac", config)
    ctl.define_rotary(1, words)
    return ctl


def plc0(ctl: PmacController, statements: int) -> None:
    ctl.plcs.load(0, "\n".join(["P1=P1+1"] * statements))
    ctl.plcs.set_enabled((0,), True)


def pr_host(ctl: PmacController, via: str, **kw) -> PrPollingHost:
    h = PrPollingHost(
        "h", ctl, 1, MOVES, random.Random(1), poll_period_s=0.01, lines_per_write=50,
        high_water=200, low_water=100, via_terminal=True, write_via=via, **kw,
    )  # fmt: skip
    h.start()
    return h


def test_each_program_line_is_one_command_answered_in_a_background_cycle():
    ctl = card()
    h = pr_host(ctl, "terminal")
    ctl.env.run(until=1.0)
    writes = ctl.log.events("host_write")
    loaded = ctl.log.events("line_loaded")
    assert len(writes) == len(loaded) == len(MOVES) == h.sent
    assert all(w.fields["lines"] == 1 for w in writes)
    # stored in program order, each line stored as the card answered its command
    assert [e.fields["text"] for e in loaded] == MOVES
    assert [e.t for e in loaded] == [w.t for w in writes]
    # an idle card answers in the next servo cycle
    period = ctl.scheduler.period_s
    assert all(0 < w.fields["reply_s"] <= period + 40e-6 for w in writes)
    assert h.write_replies == [w.fields["reply_s"] for w in writes]
    # after the first fill (to the high-water mark) the host sends &1R: answered a cycle later
    running = next(e for e in ctl.log.events("program") if e.fields["state"] == "running")
    assert running.t == pytest.approx(writes[199].t + period, abs=1e-9)
    # the host opened the rotary buffers on its own port and holds them
    assert ctl.buffer_holder is h.port and ctl.rotary_open()
    assert ctl.log.events("host_done")[0].t == writes[-1].t


def test_one_command_awaits_its_answer_at_a_time():
    ctl = card()
    pr_host(ctl, "terminal")
    ctl.env.run(until=1.0)
    ends = sorted(
        [(e.t - e.fields["reply_s"], e.t) for e in ctl.log.events("host_write", "host_pr")]
    )
    for (_, done), (sent, _) in zip(ends, ends[1:], strict=False):
        assert sent >= done


def test_write_latency_grows_with_plc0_and_direct_writes_have_none():
    means = {}
    for statements in (0, 150, 300):
        for via in ("direct", "terminal"):
            ctl = card()
            if statements:
                plc0(ctl, statements)
            h = pr_host(ctl, via)
            ctl.env.run(until=1.0)
            assert h.sent == len(MOVES) and ctl.log.events("watchdog") == []
            if via == "direct":
                assert h.write_replies == []
                assert all("reply_s" not in e.fields for e in ctl.log.events("host_write"))
            else:
                means[statements] = sum(h.write_replies) / len(h.write_replies)
    period = card().scheduler.period_s
    assert means[0] == pytest.approx(period, rel=1e-6)
    assert means[0] < means[150] < means[300]
    assert means[300] > 2.5 * means[0]  # a background cycle per RTI period (3 servo cycles)


def test_a_tripped_card_silences_the_writes_with_timeouts():
    ctl = card()
    h = NaiveHost("h", ctl, 1, MOVES * 20, random.Random(1), write_via="terminal",
                  reply_timeout_s=0.05)  # fmt: skip
    h.start()
    ctl.env.run(until=0.1)
    sent = h.sent
    assert sent > 100
    plc0(ctl, 500)  # longer than the RTI: no background cycle completes
    ctl.env.run(until=2.5)
    (trip,) = ctl.log.events("watchdog")
    writes = ctl.log.events("host_write")
    assert writes[-1].t < 0.11  # nothing answered once PLC 0 took the background
    outs = ctl.log.events("host_timeout")
    assert len(outs) >= 40 and h.timeouts == len(outs)
    # waited since the line was sent: one more timeout's worth each time
    waited = [e.fields["waited_s"] for e in outs]
    assert waited[0] == pytest.approx(0.05)
    assert all(b - a >= 0.05 - 1e-9 for a, b in zip(waited, waited[1:], strict=False))
    # the same unanswered line, again and again: nothing else goes out on the port
    assert {e.fields["command"] for e in outs} == {h.lines[h.sent]}
    assert [e for e in outs if e.t > trip.t]  # the silent card keeps timing out
    assert h.remaining > 0 and h.done_t is None


def test_a_full_buffer_answers_err006_and_the_host_resends_nothing_twice():
    ctl = card(words=60)
    h = NaiveHost("h", ctl, 1, MOVES, random.Random(1), write_via="terminal")
    h.start()
    ctl.env.run(until=3.0)
    loaded = ctl.log.events("line_loaded")
    assert [e.fields["text"] for e in loaded] == MOVES
    assert [e.fields["n"] for e in loaded] == list(range(1, len(MOVES) + 1))
    assert h.done_t is not None and ctl.log.events("host_timeout") == []
    assert min(e.fields["lines_ahead"] for e in ctl.log.events("host_write")[60:300]) > 0


def test_a_breq_routine_writing_through_the_terminal_keeps_the_program_fed():
    ctl = card(words=600)
    h = BreqInterruptHost("h", ctl, 1, MOVES, random.Random(1), lines_per_interrupt=10,
                          write_via="terminal")  # fmt: skip
    h.start()
    ctl.env.run(until=2.0)
    assert h.done_t is not None and h.interrupts > 10
    assert all(e.fields["reply_s"] > 0 for e in ctl.log.events("host_write"))
    starts = [e.t for e in ctl.log.events("move_start")]
    assert len(starts) == 400


def test_write_via_must_be_terminal_or_direct():
    with pytest.raises(ValueError, match="write_via"):
        NaiveHost("h", card(), 1, MOVES, random.Random(1), write_via="dpram")
    with pytest.raises(ValueError, match="reply_timeout_s"):
        NaiveHost("h", card(), 1, MOVES, random.Random(1), reply_timeout_s=0)


def test_a_line_answered_after_its_timeout_is_counted_once_and_the_stream_goes_on():
    ctl = card(i40=100_000)  # PLC 0 longer than the RTI, watchdog kept out of the way
    h = NaiveHost("h", ctl, 1, MOVES, random.Random(1), write_via="terminal",
                  reply_timeout_s=0.05)  # fmt: skip
    h.start()
    ctl.env.run(until=0.02)
    plc0(ctl, 500)  # no background cycle completes: the line in flight goes unanswered
    ctl.env.run(until=0.2)
    stuck = h.sent
    outs = ctl.log.events("host_timeout")
    assert len(outs) >= 3 and {e.fields["command"] for e in outs} == {MOVES[stuck]}
    ctl.plcs.set_enabled((0,), False)
    ctl.env.run(until=1.5)
    late = ctl.log.events("host_write")[stuck]
    assert late.fields["sent"] == stuck + 1 and late.fields["reply_s"] > 0.15
    loaded = ctl.log.events("line_loaded")
    assert [e.fields["text"] for e in loaded] == MOVES  # stored once, in order
    assert h.done_t is not None and h.timeouts == len(outs)
