"""BREQ and the rotary-buffer-full status bit (seed 000 "I17 Stops Interrupts", "I16 Restarts
Interrupts"; TSRM p46, p286; spec §1.2). Defaults I16 = 5, I17 = 10."""

from __future__ import annotations


def _breq(rig, since=0):
    return [(k, f["level"]) for k, _, f in rig.events("breq", since=since)]


def _loaded_rig(rig, n_lines: int):
    rig.rotary_setup()
    rig.ok("OPEN ROT")
    ks = []
    for i in range(1, n_lines + 1):
        ks.append(rig.cyc(rig.cmd(f"TM100 TA10 TS0 X{i}").t_done))
    return ks


def test_breq_pulses_when_line_loaded_below_i17(rig):
    """Seed 000: a line sent takes BREQ low at least momentarily; if still fewer than I17
    lines are ahead it goes high again (an interrupt per line) — two events at the same t."""
    ks = _loaded_rig(rig, 9)
    edges = _breq(rig)
    k_open = edges[0][0]
    assert edges[0] == (k_open, True)  # OPEN ROT: fewer than I17 ahead
    assert edges[1:] == [e for k in ks for e in ((k, False), (k, True))]
    for k, type_, _f in rig.events("line_loaded", "breq"):
        if type_ == "line_loaded":
            assert k in ks


def test_breq_stays_low_from_i17_lines_ahead(rig):
    """Seed 000: at I17 or more lines ahead BREQ is left low; the full bit is set."""
    ks = _loaded_rig(rig, 12)
    edges = _breq(rig)
    assert edges[-1] == (ks[9], False)  # the 10th line takes it low for good
    assert all(k <= ks[9] for k, _ in edges)
    word2 = int(rig.ok("??")[6:12], 16)
    assert word2 & (1 << 16)
    assert rig.ok("PR") == "12"
    assert rig.c.rotary(1)["breq"] is False


def test_breq_rises_when_fewer_than_i16_lines_ahead_after_calculation(rig):
    """Seed 000 "I16 Restarts Interrupts": after a line is calculated, fewer than I16 ahead
    sets BREQ high (and clears the full bit)."""
    _loaded_rig(rig, 12)
    rig.ok("CLOSE")
    since = rig.c.log.last_seq
    rig.ok("R")
    rig.run_until_idle()
    calc = {f["n"]: k for k, _, f in rig.events("line_calculated")}
    # 12 lines: 4 ahead (< I16 = 5) once line 8 is calculated.
    assert _breq(rig, since) == [(calc[8], True)]
    word2 = int(rig.ok("??")[6:12], 16)
    assert not word2 & (1 << 16)


def test_open_rot_reevaluates_breq(rig):
    """Seed 000: OPEN ROT takes BREQ low, then high if fewer than I17 lines are ahead."""
    _loaded_rig(rig, 3)
    rig.ok("CLOSE")
    since = rig.c.log.last_seq
    k = rig.cyc(rig.cmd("OPEN ROT").t_done)
    assert _breq(rig, since) == [(k, False), (k, True)]


def test_changing_the_addressed_cs_reevaluates_breq(rig):
    """Seed 000: changing the addressed CS with the buffers open re-evaluates its BREQ."""
    rig.ok("&2 DEFINE ROT 100")
    rig.ok("&1 DEFINE ROT 100")
    rig.ok("OPEN ROT")
    since = rig.c.log.last_seq
    k = rig.cyc(rig.cmd("&2").t_done)
    got = [(kk, f["cs"], f["level"]) for kk, _, f in rig.events("breq", since=since)]
    assert got == [(k, 2, False), (k, 2, True)]


def test_i16_i17_are_read_when_used(make_rig):
    """I16 / I17 come from the config (and may be changed on-line)."""
    rig = make_rig(i16=1, i17=2)
    ks = _loaded_rig(rig, 3)
    assert _breq(rig)[1:] == [(ks[0], False), (ks[0], True), (ks[1], False)]


def test_a_line_that_does_not_fit_gives_no_breq_edge(rig):
    """A refused line (ERR006) stores nothing and causes no BREQ edge."""
    rig.ok("&1 DEFINE ROT 2")
    rig.ok("B0")
    rig.ok("OPEN ROT")
    rig.ok("X1 Y1")
    since = rig.c.log.last_seq
    r = rig.cmd("X2")
    assert r.error == "ERR006"
    assert rig.c.log.read(since).events == []
    assert rig.ok("PR") == "1"


def test_i17_changed_on_line_after_the_buffer_exists_applies_to_the_next_line_loaded(rig):
    """I17 is read when a line is loaded, not when the buffer was defined: with 2 lines ahead,
    ``I17=3`` typed on-line (buffer closed) makes the 3rd line leave BREQ low and set the
    full bit, where the default I17 = 10 would have pulsed it."""
    ks = _loaded_rig(rig, 2)
    rig.ok("CLOSE")
    rig.ok("I17=3")
    rig.ok("OPEN ROT")
    since = rig.c.log.last_seq
    k3 = rig.cyc(rig.cmd("TM100 TA10 TS0 X3").t_done)
    assert ks[1] <= k3
    assert _breq(rig, since) == [(k3, False)]
    assert int(rig.ok("??")[6:12], 16) & (1 << 16)


def test_i16_changed_on_line_applies_to_the_next_line_calculated(rig):
    """I16 is read after each line is calculated: ``I16=2`` set before R makes BREQ rise only
    once fewer than 2 lines are ahead (with the default I16 = 5 it would rise at 4 ahead)."""
    _loaded_rig(rig, 12)
    rig.ok("CLOSE")
    rig.ok("I16=2")
    since = rig.c.log.last_seq
    rig.ok("R")
    rig.run_until_idle()
    calc = {f["n"]: k for k, _, f in rig.events("line_calculated")}
    assert _breq(rig, since) == [(calc[11], True)]  # 12 lines: 1 ahead once line 11 is done
