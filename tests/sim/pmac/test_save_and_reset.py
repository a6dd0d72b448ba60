"""SAVE, ``$$$`` and ``$$$***`` (TUM p243; spec pmac.md §11.9)."""

from __future__ import annotations


def _setup(rig):
    rig.ok("I130=1234 P10=5 M1->Y:$78802,8 &1 #1->1000X")
    for line in ("OPEN PLC 3 CLEAR", "P20=P20+1", "CLOSE"):
        rig.ok(line)


def test_save_is_acknowledged(rig):
    r = rig.cmd("SAVE")
    assert (r.reply, r.error) == ("", None)


def test_dollar3_reset_reloads_what_was_saved_and_loses_the_rest(rig):
    _setup(rig)
    rig.ok("SAVE")
    rig.ok("I135=99 P11=7 &1 DEFINE ROT 100")
    rig.ok("$$$")
    rig.run_for(0.01)
    assert [e.type for e in rig.c.log.events()].count("reset") == 1
    assert rig.ok("I130 I135 P10 P11") == "1234\r0\r5\r0"
    assert rig.ok("M1->") == "Y:$78802,8"
    assert rig.ok("&1 #1->") == "1000X"
    assert rig.c.coord_system(1).rotary is None  # buffers are not saved
    assert rig.ok("LIST PLC 3") == "P20=P20+1\rRET"


def test_dollar3_without_a_save_is_the_factory_state(rig):
    _setup(rig)
    rig.ok("$$$")
    rig.run_for(0.01)
    assert rig.ok("I130 P10") == "2000\r0"  # Ixx30 factory 2000
    assert rig.ok("M1->") == "*"
    assert rig.cmd("LIST PLC 3").error == "ERR003"


def test_dollar3_stars_reinitialises_to_factory_and_keeps_the_saved_copy_unused(rig):
    _setup(rig)
    rig.ok("SAVE")
    rig.ok("$$$***")
    rig.run_for(0.01)
    assert rig.ok("I130 I108 I68") == "2000\r96\r15"
    assert rig.ok("M1->") == "*"
    rig.ok("$$$")  # the flash copy is still there
    rig.run_for(0.01)
    assert rig.ok("I130") == "1234"


def test_the_reset_answers_first_then_acts(rig):
    rig.ok("P1=3")
    r = rig.cmd("$$$")
    assert (r.reply, r.error) == ("", None)
