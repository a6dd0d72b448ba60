"""Turbo PMAC data gathering (issue 34): I5000-I5051, DEFINE / DELETE GATHER, GATHER,
ENDGATHER, LIST GATHER, in virtual time.

The rules come from the Turbo SRM (TSRM p170 I5000 / I5001-I5048, p171 I5049-I5051, p307
DEFINE GATHER, p315 DELETE GATHER); the source-address form and the LIST GATHER word order
from Delta Tau's own gathering tool (dls-pmac-control ``gather.py`` / ``gatherchannel.py``),
which is what a host reading a real card does. Samples are asserted at servo cycles against
the event log (the ``gather`` events, a jog's ``jog`` events) and against values written into
card memory with ``W``.
"""

from __future__ import annotations

import pytest

from .conftest import Rig

CMD_POS_M1 = "$800088"  # D:$000088 motor 1 commanded position (registers.py)
ACT_POS_M1 = "$80008B"
FE_M1 = "$800091"
VEL_M1 = "$40009D"  # X: 24 bits


def decode_list_gather(reply: str, widths: list[int]) -> list[list[int]]:
    """A host's decoding of ``LIST GATHER`` (the way dls-pmac-control reads a card): every
    12-digit token is two 24-bit words, characters 6-11 first; a 48-bit source is the next
    two words (low, high); a sample of an odd number of words is followed by one pad word."""
    words: list[int] = []
    for tok in reply.split():
        assert len(tok) == 12
        words += (int(tok[6:], 16), int(tok[:6], 16))
    per_sample = sum(w // 24 for w in widths)
    per_sample += per_sample % 2
    samples = []
    for i in range(0, len(words), per_sample):
        chunk, row, j = words[i:i + per_sample], [], 0
        for w in widths:
            if w == 24:
                row.append(chunk[j])
                j += 1
            else:
                row.append(chunk[j + 1] << 24 | chunk[j])
                j += 2
        samples.append(row)
    return samples


def gather_events(rig: Rig, since: int = 0) -> list[tuple[int, dict]]:
    return [(k, f) for k, _, f in rig.events("gather", since=since)]


@pytest.fixture
def memory_rig() -> Rig:
    """A card with known words at $1000/$1001 of plain memory (written with ``W``)."""
    rig = Rig()
    rig.ok("WY:$1000,$123456")
    rig.ok("WX:$1000,$ABCDEF")
    rig.ok("WY:$1001,7")
    return rig


def test_tsrm_p171_gathering_starts_on_the_next_servo_cycle_and_samples_every_i5049(
        memory_rig):
    """I5049 = 3: the first sample on the servo cycle after GATHER was processed, then every
    third cycle; ENDGATHER stops it (the ``gather`` events say when)."""
    rig = memory_rig
    rig.ok("I5001=$001000 I5050=1 I5049=3")
    rig.ok("DEFINE GATHER 1000")
    since = rig.c.log.last_seq
    rig.ok("GATHER")
    (k0, started), = gather_events(rig, since)
    assert started == {"state": "started", "sources": ["I5001"], "period": 3,
                       "capacity": 1000}  # one word + pad: a long word a sample
    rig.run_for(40 * rig.period)
    rig.ok("ENDGATHER")
    k_end, stopped = gather_events(rig, since)[-1]
    rec = rig.c.gather.recording()
    assert rec.cycles[0] == k0 + 1
    assert list(rec.cycles) == list(range(k0 + 1, k_end + 1, 3))
    assert set(rec.values) == {(0x123456,)}
    assert stopped == {"state": "stopped", "reason": "endgather", "samples": len(rec.cycles)}
    rig.run_for(20 * rig.period)
    assert rig.c.gather.recording().cycles == rec.cycles  # nothing after ENDGATHER


def test_samples_are_the_motor_registers_at_their_servo_cycle(rig):
    """Commanded and actual position (D:$88 / D:$8B, 1/(Ixx08*32) counts), following error
    (D:$91) and velocity (X:$9D, 1/(Ixx09*32) counts per cycle) of motor 1 during a jog: 0
    before the jog's ``start`` event, the target after its ``end`` event, rising between."""
    rig.ok(f"I5001={CMD_POS_M1} I5002={ACT_POS_M1} I5003={FE_M1} I5004={VEL_M1}")
    rig.ok("I5050=$F I5049=1 I122=10")
    rig.ok("DEFINE GATHER")
    rig.ok("GATHER")
    rig.ok("#1J=1000")
    rig.run_for(0.8)
    rig.ok("ENDGATHER")
    jog = {f["state"]: k for k, _, f in rig.events("jog")}
    scale = int(rig.c.vars.I(108)) * 32
    rec = rig.c.gather.recording()
    rows = dict(zip(rec.cycles, rec.values, strict=True))
    assert rec.cycles == tuple(range(rec.cycles[0], rec.cycles[-1] + 1))
    assert all(rows[k][:3] == (0, 0, 0) for k in rows if k <= jog["start"])
    assert all(rows[k][:2] == (1000 * scale, 1000 * scale) for k in rows if k >= jog["end"])
    moving = [rows[k][0] for k in sorted(rows) if jog["start"] <= k <= jog["end"]]
    assert moving == sorted(moving) and moving[0] < moving[-1]
    assert all(v[2] == 0 for v in rec.values)  # the loop tracks exactly (docs/pmac.md)
    velocity = [rows[k][3] for k in sorted(rows) if jog["start"] < k < jog["end"]]
    assert max(velocity) > 0 and rows[rec.cycles[-1]][3] == 0


def test_tsrm_p170_i5000_0_stops_when_the_buffer_is_full(memory_rig):
    """Three 24-bit sources + pad = 2 long words a sample: DEFINE GATHER 10 holds 5 samples;
    with I5000 = 0 the fifth fills it and gathering stops by itself."""
    rig = memory_rig
    rig.ok("I5001=$001000 I5002=$401000 I5003=$001001 I5050=7 I5049=2 I5000=0")
    rig.ok("DEFINE GATHER 10")
    since = rig.c.log.last_seq
    rig.ok("GATHER")
    rig.run_for(100 * rig.period)
    (k0, _), (k_full, stopped) = gather_events(rig, since)
    assert stopped == {"state": "stopped", "reason": "full", "samples": 5}
    assert k_full == k0 + 1 + 4 * 2
    assert rig.c.gather.recording().cycles == tuple(range(k0 + 1, k_full + 1, 2))
    assert rig.c.gather.running is False
    assert rig.ok("DELETE GATHER") == ""  # not in progress any more (TSRM p315)


def test_tsrm_p170_i5000_1_wraps_and_keeps_the_newest_samples(memory_rig):
    """I5000 = 1: the buffer wraps; the recording is the newest 5 samples in time order and
    LIST GATHER answers the slots in memory order (the newest samples at the start)."""
    rig = memory_rig
    rig.ok("I5001=$001001 I5050=1 I5049=1 I5000=1")
    rig.ok("DEFINE GATHER 5")  # one 24-bit source + pad: one long word a sample
    rig.ok("GATHER")
    rig.run_for(3 * rig.period)
    rig.ok("WY:$1001,8")  # the value changes while gathering
    rig.run_for(20 * rig.period)
    rig.ok("ENDGATHER")
    rec = rig.c.gather.recording()
    assert rec.wrapped and len(rec.cycles) == 5
    assert rec.cycles == tuple(range(rec.cycles[0], rec.cycles[0] + 5))
    assert set(rec.values) == {(8,)}
    assert rig.ok("LIST GATHER") == " ".join(["000000000008"] * 5)


def test_tsrm_p171_i5049_0_is_one_sample_per_gather(memory_rig):
    rig = memory_rig
    rig.ok("I5001=$001001 I5050=1 I5049=0")
    rig.ok("DEFINE GATHER 100")
    since = rig.c.log.last_seq
    rig.ok("GATHER")
    rig.run_for(20 * rig.period)
    (k0, _), (k1, stopped) = gather_events(rig, since)
    assert (k1, stopped) == (k0 + 1, {"state": "stopped", "reason": "single", "samples": 1})
    assert rig.c.gather.recording().values == ((7,),)


def test_tsrm_p171_masks_select_sources_in_order_i5001_to_i5048(memory_rig):
    """I5050 bit n selects I50(n+1), I5051 bit n selects I50(n+25); the sample is in source
    order whatever the bits' order."""
    rig = memory_rig
    rig.ok("I5002=$001001 I5005=$001000 I5026=$401000 I5048=$001001")
    rig.ok("I5050=$12 I5051=$800002 I5049=1")
    rig.ok("DEFINE GATHER 100")
    rig.ok("GATHER")
    rig.run_for(3 * rig.period)
    rec = rig.c.gather.recording()
    assert [s.name for s in rec.sources] == ["I5002", "I5005", "I5026", "I5048"]
    assert rec.values[0] == (7, 0x123456, 0xABCDEF, 7)


def test_list_gather_is_what_a_host_decodes_as_a_cards_answer(memory_rig):
    """A 24-bit Y word and a 48-bit D word (X high, Y low) per sample: three 24-bit words and
    a pad, two 12-digit tokens, characters 6-11 the first word of each pair."""
    rig = memory_rig
    rig.ok("I5001=$001000 I5002=$801000 I5050=3 I5049=1 I5000=0")
    rig.ok("DEFINE GATHER 4")
    rig.ok("GATHER")
    rig.run_for(10 * rig.period)
    reply = rig.ok("LIST GATHER")
    assert reply.split()[:2] == ["123456123456", "000000ABCDEF"]
    assert decode_list_gather(reply, [24, 48]) == [[0x123456, 0xABCDEF123456]] * 2


def test_list_gather_lines_hold_eight_words(memory_rig):
    rig = memory_rig
    rig.ok("I5001=$001001 I5050=1 I5049=1 I5000=0")
    rig.ok("DEFINE GATHER 20")
    rig.ok("GATHER")
    rig.run_for(30 * rig.period)
    lines = rig.ok("LIST GATHER").split("\r")
    assert [len(line.split()) for line in lines] == [8, 8, 4]


def test_tsrm_p307_define_gather_on_a_buffer_rewinds_it(memory_rig):
    """DEFINE GATHER on an existing buffer: storage back to the start, LIST GATHER lists
    nothing until the next GATHER."""
    rig = memory_rig
    rig.ok("I5001=$001001 I5050=1 I5049=1")
    rig.ok("DEFINE GATHER 100")
    rig.ok("GATHER")
    rig.run_for(5 * rig.period)
    rig.ok("ENDGATHER")
    assert rig.ok("LIST GATHER") != ""
    rig.ok("DEFINE GATHER 100")
    assert rig.ok("LIST GATHER") == ""


def test_tsrm_p307_p315_define_and_delete_gather_are_refused_while_gathering(memory_rig):
    rig = memory_rig
    rig.ok("I5001=$001001 I5050=1 I5049=1")
    rig.ok("DEFINE GATHER 1000")
    rig.ok("GATHER")
    for cmd in ("DEFINE GATHER 10", "DELETE GATHER", "GATHER"):
        reply = rig.cmd(cmd)
        assert reply.error == "ERR003", cmd
        assert "in progress" in reply.detail[1]
    assert rig.c.gather.words == 1000 and rig.c.gather.running
    rig.ok("ENDGATHER")
    rig.ok("DELETE GATHER")
    assert rig.c.gather.words is None


def test_size_shrinks_by_the_gather_buffer_and_a_buffer_larger_than_free_is_err006(rig):
    """TSRM p307: the buffer takes open memory (SIZE reports what is left); more than is free
    is ERR006 and changes nothing."""
    free = int(rig.ok("SIZE"))
    rig.ok("DEFINE GATHER 1000")
    assert int(rig.ok("SIZE")) == free - 1000
    assert rig.cmd(f"DEFINE GATHER {free + 1}").error == "ERR006"
    assert rig.c.gather.words == 1000
    rig.ok(f"DEFINE GATHER {free}")  # its own words count as free for the new size
    assert rig.ok("SIZE") == "0"


@pytest.mark.parametrize(("setup", "named"), [
    ("I5001=$012345 I5050=1", "I5001=$012345"),  # plain memory nothing holds
    ("I5003=$200088 I5050=4", "I5003=$200088"),  # first digit 2: not a part (p170)
    ("I5001=$0A0088 I5050=1", "bit 19"),
    ("I5050=0 I5051=0", "select no source"),
])
def test_bad_gather_sources_are_refused_at_gather_naming_them(rig, setup, named):
    rig.ok(setup)
    rig.ok("DEFINE GATHER 100")
    since = rig.c.log.last_seq
    reply = rig.cmd("GATHER")
    assert reply.error == "ERR003"
    assert named in reply.detail[1]
    assert rig.events("gather", since=since) == [] and not rig.c.gather.running


def test_gather_needs_a_buffer(rig):
    rig.ok("I5001=$800088 I5050=1")
    reply = rig.cmd("GATHER")
    assert reply.error == "ERR003" and "DEFINE GATHER" in reply.detail[1]


def test_an_m_variable_address_is_a_gather_source(rig):
    """Any M-variable's address can be gathered: M1 at Y:$3000 (plain memory), written by
    the program as it runs."""
    rig.ok("M1->Y:$3000,0,24")
    rig.ok("I5001=$003000 I5050=1 I5049=1")
    rig.ok("DEFINE GATHER 100")
    rig.ok("GATHER")
    rig.run_for(3 * rig.period)
    rig.ok("M1=42")
    rig.run_for(3 * rig.period)
    rig.ok("ENDGATHER")
    values = [v for (v,) in rig.c.gather.recording().values]
    assert values[0] == 0 and values[-1] == 42 and values == sorted(values)


@pytest.mark.parametrize("text", ["GATHER TRIGGER", "GAT TRIGGER", "gather trigger"])
def test_gather_trigger_waits_for_the_trigger_input_to_rise(memory_rig, text):
    """``GATHER TRIGGER`` (TSRM on-line ``GATHER``; the page was not found, the trigger is
    ``[INF]``, docs/pmac.md): armed at the command, nothing gathered while the trigger input
    (Y:$078800 bit 0) stays low; the servo cycle that finds it risen takes the first sample,
    then every I5049 cycles as ``GATHER``."""
    rig = memory_rig
    rig.ok("I5001=$001000 I5050=1 I5049=2")
    rig.ok("DEFINE GATHER 100")
    since = rig.c.log.last_seq
    rig.ok(text)
    (_, armed), = gather_events(rig, since)
    assert armed == {"state": "armed", "input": "Y:$078800,0"}
    assert rig.c.gather.running
    rig.run_for(20 * rig.period)
    assert rig.c.gather.recording().cycles == ()
    rig.ok("WY:$078800,$10")  # another input: no trigger
    rig.run_for(5 * rig.period)
    assert rig.c.gather.recording().cycles == ()
    rig.ok("WY:$078800,$11")
    t_edge = rig.c.env.now
    rig.run_for(10 * rig.period)
    rig.ok("ENDGATHER")
    events = gather_events(rig, since)
    k_start, started = events[1]
    assert started == {"state": "started", "sources": ["I5001"], "period": 2,
                       "capacity": 100}
    rec = rig.c.gather.recording()
    # the write is answered on a servo cycle; that cycle's interrupt (after the write in
    # queue order) or the next one finds the input high
    assert k_start - rig.cyc(t_edge) in (0, 1)
    assert rec.cycles[0] == k_start
    assert list(rec.cycles) == list(range(k_start, rec.cycles[-1] + 1, 2))
    assert set(rec.values) == {(0x123456,)}


def test_gather_trigger_needs_a_rising_edge_and_endgather_disarms_it(memory_rig):
    """An input already high at ``GATHER TRIGGER`` does not trigger until it has been low
    ``[INF]``; ``ENDGATHER`` while armed stops with no sample, and the buffer may be
    deleted then (TSRM p315: gathering is no longer in progress)."""
    rig = memory_rig
    rig.ok("I5001=$001000 I5050=1 I5049=1")
    rig.ok("DEFINE GATHER 100")
    rig.ok("WY:$078800,1")
    rig.ok("GATHER TRIGGER")
    rig.run_for(10 * rig.period)
    assert rig.c.gather.recording().cycles == ()
    assert rig.cmd("DELETE GATHER").error == "ERR003"  # armed: in progress
    rig.ok("WY:$078800,0")
    rig.run_for(3 * rig.period)
    rig.ok("WY:$078800,1")
    rig.run_for(3 * rig.period)
    assert len(rig.c.gather.recording().cycles) >= 2
    rig.ok("ENDGATHER")
    rig.ok("GATHER TRIGGER")
    rig.run_for(5 * rig.period)
    since = rig.c.log.last_seq
    rig.ok("ENDGATHER")
    (_, stopped), = gather_events(rig, since)
    assert stopped == {"state": "stopped", "reason": "endgather", "samples": 0}
    rig.ok("DELETE GATHER")


@pytest.mark.parametrize("text", ["END GATHER", "END Gat", "end gather", "ENDGATHER", "ENDG"])
def test_blanks_inside_endgather_do_not_matter(memory_rig, text):
    """TSRM p23: ``END GATHER`` is ``ENDGATHER``: each spelling ends the gathering."""
    rig = memory_rig
    rig.ok("I5001=$001001 I5050=1 I5049=1")
    rig.ok("DEFINE GATHER 100")
    rig.ok("GATHER")
    rig.ok(text)
    assert not rig.c.gather.running


def test_a_reset_ends_gathering_and_the_buffer(memory_rig):
    rig = memory_rig
    rig.ok("I5001=$001001 I5050=1 I5049=1")
    rig.ok("DEFINE GATHER 100")
    rig.ok("GATHER")
    rig.c.reset()
    rig.run_for(10 * rig.period)
    assert rig.c.gather.words is None and not rig.c.gather.running
    assert rig.cmd("LIST GATHER").error == "ERR003"
