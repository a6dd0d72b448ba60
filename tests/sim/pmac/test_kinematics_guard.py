"""Work a kinematic program can make long is bounded (issue 33 item 4).

A forward program that loops ran 100 000 statements per PMATCH (0.3-0.8 s of the event loop,
``/health`` p99 768 ms while one host repeated ``&1 PMATCH``). The guard is now
``MAX_STEPS`` statements — what one ~4 ms slice holds — counted per assignment, test and
jump; past it the run is abandoned as a runaway loop (a ``kinematics`` event naming it).
Counts, not durations.
"""

from __future__ import annotations

from motionsim.sim.pmac.kinematics.subroutine import MAX_STEPS


def _forward(rig, *lines: str) -> None:
    rig.ok("&1 #1->I #2->I")
    rig.ok("&1 OPEN FORWARD CLEAR")
    for line in lines:
        rig.ok(line)
    rig.ok("CLOSE")
    rig.ok("I5150=1")


def test_the_guard_is_5000_statements() -> None:
    assert MAX_STEPS == 5_000


def test_a_looping_forward_program_stops_at_the_guard(rig):
    """Each turn of ``WHILE (1>0) Q40=Q40+1 ENDWHILE`` is three statements (the test, the
    assignment, the jump back): the run stops after MAX_STEPS of them."""
    _forward(rig, "Q7=0", "Q8=0", "WHILE (1>0)", "Q40=Q40+1", "ENDWHILE")
    since = rig.c.log.last_seq
    rig.cmd("&1 PMATCH")
    rig.run_for(0.01)
    turns = rig.c.get_variable("&1Q40")
    assert (MAX_STEPS - 4) // 3 - 1 <= turns <= MAX_STEPS // 3
    kin = rig.events("kinematics", since=since)
    assert kin and "no end after 5000 statements" in kin[0][2]["error"]


def test_a_long_flat_forward_program_past_the_guard_is_refused_each_run(rig):
    _forward(rig, *(f"Q{7 + k % 2}={k}" for k in range(MAX_STEPS + 1)))
    since = rig.c.log.last_seq
    rig.cmd("&1 PMATCH")
    rig.run_for(0.01)
    kin = rig.events("kinematics", since=since)
    assert kin and f"more than the {MAX_STEPS}" in kin[0][2]["error"]
    assert rig.c.get_variable("&1Q7") == 0  # nothing of it ran


def test_a_loop_within_the_guard_still_ends(rig):
    _forward(rig, "Q7=0", "Q8=0", "Q40=0", "WHILE (Q40<1000)", "Q40=Q40+1", "ENDWHILE")
    since = rig.c.log.last_seq
    rig.cmd("&1 PMATCH")
    rig.run_for(0.01)
    assert rig.c.get_variable("&1Q40") == 1000
    assert all("error" not in f for _, _, f in rig.events("kinematics", since=since))
