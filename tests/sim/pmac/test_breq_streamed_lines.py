"""BREQ for the lines a host streams (seed 000 "I16 Restarts Interrupts"; TSRM p46, p286):
plain move lines — axis words only, the mode and TM set earlier — are calculated on a short
path of their own, which must follow the same I16 rule; and a BREQ rising edge lost at a line
store (an injected fault) leaves the level high with nobody told."""

from __future__ import annotations

from motionsim.sim.faults import EdgeLoss, Selector

from tests.sim.pmac.test_breq import _breq


def _streamed(rig, n_moves: int) -> None:
    """A modal line, then ``n_moves`` plain ABS move lines (``X1``, ``X2``, ...)."""
    rig.rotary_setup()
    rig.ok("OPEN ROT")
    rig.ok("ABS LINEAR TM100 TA10 TS0")
    for i in range(1, n_moves + 1):
        rig.ok(f"X{i}")
    rig.ok("CLOSE")


def _run(rig) -> dict[int, int]:
    rig.ok("R")
    rig.run_until_idle()
    return {f["n"]: k for k, _, f in rig.events("line_calculated")}


def test_streamed_plain_lines_raise_breq_below_i16_after_calculation(rig):
    """12 lines ahead (the full bit set at I17 = 10): BREQ rises, and the full bit clears,
    once a calculated line leaves fewer than I16 = 5 ahead: after line 9 of 13 (4 ahead)."""
    _streamed(rig, 12)
    assert int(rig.ok("??")[6:12], 16) & (1 << 16)
    since = rig.c.log.last_seq
    calc = _run(rig)
    assert _breq(rig, since) == [(calc[9], True)]
    assert not int(rig.ok("??")[6:12], 16) & (1 << 16)


def test_i16_changed_on_line_applies_to_streamed_plain_lines(rig):
    """``I16=2`` typed after loading: BREQ rises only once fewer than 2 are ahead, after
    line 12 of 13 (where the default I16 = 5 would raise it after line 9)."""
    _streamed(rig, 12)
    rig.ok("I16=2")
    since = rig.c.log.last_seq
    calc = _run(rig)
    assert _breq(rig, since) == [(calc[12], True)]


def test_a_lost_rising_edge_at_a_line_store_is_not_signalled_but_the_level_is_high(rig):
    """With the next rising edge lost, the line stored with fewer than I17 ahead takes BREQ
    low (signalled) and high again unsignalled: a ``fault`` event instead of the rising
    ``breq`` one, and the level reads high. The next line pulses it as usual."""
    rig.rotary_setup()
    rig.ok("OPEN ROT")
    rig.c.card_faults.add_edge_loss(EdgeLoss("lose", 1, Selector()))
    since = rig.c.log.last_seq
    rig.ok("ABS LINEAR TM100 TA10 TS0 X1")
    seen = [(t, f.get("level", f.get("kind"))) for _, t, f in rig.events("breq", "fault",
                                                                         since=since)]
    assert seen == [("breq", False), ("fault", "breq_lost")]
    assert rig.c.rotary(1)["breq"] is True
    since = rig.c.log.last_seq
    rig.ok("X2")
    assert [f["level"] for _, _, f in rig.events("breq", since=since)] == [False, True]


def test_i16_typed_while_streamed_lines_run_applies_to_the_next_line_calculated(rig):
    """I16 is read after each calculated line, also mid-stream: ``I16=2`` typed while the
    program runs (lines 1-4 calculated) makes BREQ rise after line 12 of 13, not after 9."""
    _streamed(rig, 12)
    since = rig.c.log.last_seq
    rig.ok("R")
    while len(rig.events("line_calculated", since=since)) < 4:
        rig.c.env.step()
    calculated = len(rig.events("line_calculated", since=since))
    rig.ok("I16=2")
    assert len(rig.events("line_calculated", since=since)) == calculated < 9
    rig.run_until_idle()
    calc = {f["n"]: k for k, _, f in rig.events("line_calculated", since=since)}
    assert _breq(rig, since) == [(calc[12], True)]
