"""Re-addressing the coordinate system that is already addressed is not a change (seed 000:
BREQ is re-evaluated "when ... the addressed coordinate system is changed"), and the rotary
buffer full bit keeps its I16 / I17 hysteresis whatever the host polls with (TSRM p286: set at
I17 or more lines ahead, cleared only when fewer than I16). Defaults I16 = 5, I17 = 10."""

from __future__ import annotations


def _breq(rig, since):
    return [(k, f["cs"], f["level"]) for k, _, f in rig.events("breq", since=since)]


def _full_bit(rig) -> bool:
    return bool(int(rig.ok("??")[6:12], 16) & (1 << 16))


def _two_buffers_open(rig, lines: int = 0):
    rig.ok("&2 DEFINE ROT 200")
    rig.ok("&1 DEFINE ROT 200")
    rig.ok("&1 B0")
    rig.ok("OPEN ROT")
    for i in range(1, lines + 1):
        rig.ok(f"TM100 TA10 TS0 X{i}")


def test_seed000_polling_with_the_addressed_cs_prefix_gives_no_breq_pulse(rig):
    """``&1 PR`` and ``&1??`` polled with CS 1 already addressed: no BREQ edge (no interrupt
    per poll); the replies are unchanged."""
    _two_buffers_open(rig, 3)
    since = rig.c.log.last_seq
    for _ in range(5):
        assert rig.ok("&1 PR") == "3"
        rig.ok("&1??")
        rig.ok("&1")
    assert _breq(rig, since) == []


def test_seed000_an_actual_change_of_the_addressed_cs_reevaluates_breq_at_that_cycle(rig):
    _two_buffers_open(rig, 3)
    since = rig.c.log.last_seq
    k2 = rig.cyc(rig.cmd("&2").t_done)
    k1 = rig.cyc(rig.cmd("&1 PR").t_done)
    assert _breq(rig, since) == [(k2, 2, False), (k2, 2, True), (k1, 1, False), (k1, 1, True)]


def test_tsrm_p286_full_bit_set_at_i17_survives_polls_until_fewer_than_i16(rig):
    """10 lines loaded: full. Running calculates lines down to between I16 and I17 ahead;
    neither ``&1??`` polls nor a change of the addressed CS and back clears the bit; it is
    cleared only when calculation brings the count below I16."""
    _two_buffers_open(rig, 10)
    assert _full_bit(rig)
    rig.ok("R")
    rig.run_for(0.05)
    assert 5 <= int(rig.ok("PR")) < 10
    for _ in range(3):
        assert int(rig.ok("&1??")[6:12], 16) & (1 << 16)
    rig.ok("&2")
    rig.ok("&1")
    assert rig.c.rotary(1)["breq"] is True  # BREQ itself follows I17 on the change (seed 000)
    assert _full_bit(rig)
    while int(rig.ok("PR")) >= 5:
        assert _full_bit(rig)
        rig.run_for(0.02)
    assert not _full_bit(rig)
