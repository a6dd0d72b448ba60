"""A program that ran out of lines (``waiting``) with the feed override at ``%0``: lines that
arrive are calculated but nothing moves; ``%`` above 0 starts them, and the program is
``running`` again (a ``program`` event) while they execute — the state a host polls, and the
one under which falling behind in calculation is a run-time error (TUM p339)."""

from __future__ import annotations


def test_moves_started_by_raising_the_feed_override_make_a_waiting_program_running(rig):
    rig.rotary_setup()
    rig.ok("R")
    rig.ok("%0")
    rig.run_for(1.0)  # the override slews down at Isx94 (TSRM p429): at 0 well before 1 s
    rig.c.load_lines(1, ["TM100 X1", "X2"])
    rig.run_for(0.05)
    assert rig.events("move_start") == []
    assert [f["state"] for _, _, f in rig.events("program")] == ["running", "waiting"]
    since = rig.c.log.last_seq
    rig.ok("%100")
    rig.run_until_idle(3.0)
    started = [k for k, _, f in rig.events("move_start", since=since)]
    states = [(k, f["state"]) for k, _, f in rig.events("program", since=since)]
    assert len(started) == 2
    assert states == [(started[0], "running"), (states[-1][0], "waiting")]
    assert states[-1][0] > started[1]
