"""Motion-program commands of issue 37 item 4.

* ``HOME{list}`` / ``HOMEZ{list}`` in a motion program: "the homing search move can be
  executed through either an on-line command ... or a motion program statement" (PMAC User
  Manual p130, "Home Command"); HOME is a lookahead break (spec §0 fact 10, TUM p341:
  DWELL, RAPID, HOME, PSET stop lookahead): the move before it ends in a stop, the move after
  it is calculated once the searches have ended. Motor lists and ranges (``HOME1,2``,
  ``HOMEZ1..3``) as on-line (TSRM HOME / HOMEZ program commands ``[BK]``).
* Cutter radius compensation ``CC0``-``CC3`` and ``CCR{data}`` (TSRM program commands; TUM
  "Cutter Radius Compensation") is valid Turbo PMAC that motionsim does not simulate: each is
  answered naming it, never "C needs a value", and the buffer is unchanged.
"""

from __future__ import annotations

import pytest


def _setup(rig):
    rig.ok("&1 #1->1000X #2->1000Y")
    rig.rotary_setup()


def test_pum_p130_home_in_a_rotary_program_homes_between_moves(rig):
    _setup(rig)
    rig.c.load_lines(1, ["ABS LINEAR TA10 TS0 TM100 X1 Y1", "HOME1,2", "X2 Y0.5"])
    rig.ok("R")
    rig.run_until_idle()
    ev = [(k, t, f) for k, t, f in rig.events("move_start", "move_end", "jog", "home")]
    end1 = next(k for k, t, f in ev if t == "move_end" and f["n"] == 1)
    starts = [k for k, t, f in ev if t == "jog" and f["state"] == "start"]
    ends = [k for k, t, f in ev if t == "jog" and f["state"] == "end"]
    start3 = next(k for k, t, f in ev if t == "move_start" and f["n"] == 3)
    # both searches start together after the first move has stopped (+ Ixx92 = 10 ms)
    assert len(starts) == 2 and starts[0] == starts[1] > end1
    assert (starts[0] - end1) == pytest.approx(rig.ms_cycles(10), abs=1)
    # the next move waits for the last search to end (the break), then starts from home
    assert len(ends) == 2 and start3 >= max(ends)
    assert [f["motor"] for _, t, f in ev if t == "home"] == [1, 2]
    # after HOME the axes are at 0 (motor zero), so ABS X2 Y0.5 ends at 2000 / 500 counts
    assert rig.c.positions(1) == {"X": pytest.approx(2.0), "Y": pytest.approx(0.5)}
    assert rig.c.motor_position(1) == pytest.approx(2000.0)
    assert rig.c.motor_position(2) == pytest.approx(500.0)


def test_pum_p130_homez_range_in_a_fixed_program_takes_no_motion(rig):
    """HOMEZ1..2 (zero-move homing): the present positions become the motor zeros at once;
    the program goes on without a jog move."""
    rig.ok("&1 #1->1000X #2->1000Y")
    rig.ok("OPEN PROG 5 CLEAR")
    rig.ok("ABS LINEAR TA10 TS0 TM100 X1 Y1")
    rig.ok("HOMEZ1..2")
    rig.ok("X0.5 Y0.5")
    rig.ok("CLOSE")
    rig.ok("&1 B5 R")
    rig.run_until_idle()
    assert [f["state"] for _, _, f in rig.events("program")][-1] == "stopped"
    assert rig.events("jog") == []
    # X1 then homed (axis 0 there), then ABS X0.5: half a unit further on
    assert rig.c.motor_position(1) == pytest.approx(500.0)
    assert rig.c.positions(1) == {"X": pytest.approx(0.5), "Y": pytest.approx(0.5)}


def test_home_list_in_a_program_is_stored_and_listed(rig):
    rig.ok("OPEN PROG 6 CLEAR")
    rig.ok("HOME1,3")
    rig.ok("CLOSE")
    listing = rig.ok("LIST PROG 6")
    assert "HOME1,3" in listing.replace(" ", "")


def test_home_list_on_line_still_homes_at_once(rig):
    rig.ok("HOMEZ1")
    assert rig.ok("#1?")  # accepted; on-line as before


@pytest.mark.parametrize("line,name", [
    ("CC0", "CC0"), ("CC1", "CC1"), ("CC2", "CC2"), ("CC3", "CC3"), ("CCR0.25", "CCR"),
    ("X1 CC1 Y2", "CC1"),
])
def test_tsrm_cutter_compensation_is_refused_by_name_and_changes_no_buffer(rig, line, name):
    rig.rotary_setup()
    port = rig.c.open_port("host")
    rig.ok("OPEN ROT", port)
    since = rig.c.log.last_seq
    r = rig.cmd(line, port)
    assert r.error is not None and "ERR003" in str(r.error)
    assert r.detail is not None and r.detail[0] == "not_simulated"
    assert r.detail[1].startswith(f"{name} is a valid Turbo PMAC command")
    assert "needs a value" not in r.detail[1]
    assert rig.c.rotary(1)["used_words"] == 0
    assert rig.events("line_loaded", since=since) == []
