"""The rotary buffer's "full" status bit and BREQ on re-evaluation, and its word accounting.

Seed 000 / spec §1.2: ``OPEN ROT`` (or a change of the addressed CS) takes BREQ low, then high
if fewer than I17 lines are ahead. TSRM p286: the "rotary buffer full" bit is set at I17 or
more lines ahead and cleared only below I16 (hysteresis). TUM p337: the buffer is a ring of
words; executed lines give theirs back.
"""

from __future__ import annotations

from types import SimpleNamespace

import simpy
from motionsim.sim.events import EventLog
from motionsim.sim.pmac.buffers.rotary import RotaryBuffer


def _reopen(rig, i16: int, i17: int) -> tuple[bool, bool, list[bool]]:
    """Set I16 / I17, OPEN ROT, CLOSE: (full, BREQ, the BREQ edges OPEN ROT gave)."""
    rig.ok(f"I16={i16}")
    rig.ok(f"I17={i17}")
    since = rig.c.log.last_seq
    rig.ok("OPEN ROT")
    edges = [f["level"] for _, _, f in rig.events("breq", since=since)]
    rig.ok("CLOSE")
    rot = rig.c.coord(1)["rotary"]
    return rot["full"], rot["breq"], edges


def test_open_rot_sets_full_at_i17_ahead_and_clears_it_only_below_i16(rig):
    rig.ok("I16=1")
    rig.ok("I17=2")
    rig.rotary_setup()
    rig.c.load_lines(1, ["X1", "X2", "X3"])  # not running: 3 lines stay ahead
    assert rig.c.coord(1)["rotary"]["lines_ahead"] == 3
    assert rig.c.coord(1)["rotary"]["full"] is True
    assert _reopen(rig, 1, 2) == (True, False, [])  # 3 > I17: full, BREQ stays low
    assert _reopen(rig, 1, 3) == (True, False, [])  # 3 = I17: still full, no request
    assert _reopen(rig, 2, 5) == (True, True, [True])  # I16 < 3 < I17: full kept, BREQ high
    assert _reopen(rig, 3, 5) == (True, True, [False, True])  # I16 = 3 < I17: kept, a pulse
    assert _reopen(rig, 4, 5) == (False, True, [False, True])  # 3 < I16: cleared, a pulse
    assert _reopen(rig, 2, 5) == (False, True, [False, True])  # I16 < 3 < I17: stays clear
    assert _reopen(rig, 3, 5) == (False, True, [False, True])  # 3 = I16: not below, clear
    assert _reopen(rig, 1, 3) == (True, False, [False])  # 3 = I17 again: set, BREQ low
    assert _reopen(rig, 4, 5) == (False, True, [True])  # cleared again below I16 (was low)
    assert _reopen(rig, 1, 2) == (True, False, [False])  # 3 > I17: set from clear


def test_a_buffer_defined_at_the_terminal_starts_empty_and_not_full(rig):
    rig.ok("&1 DEFINE ROT 600")
    rot = rig.c.coord(1)["rotary"]
    assert rot["full"] is False and rot["lines_ahead"] == 0 and rot["used_words"] == 0


def test_on_line_i16_i17_set_before_the_first_line_are_honoured(rig):
    """I16 / I17 are read when a line is stored, whenever they were set (TSRM p46)."""
    rig.rotary_setup()
    rig.ok("I17=2")
    since = rig.c.log.last_seq
    rig.c.load_lines(1, ["X1", "X2"])
    # line 1 (1 ahead < I17): BREQ up; line 2 (2 ahead = I17): down, and it stays down
    assert [f["level"] for _, _, f in rig.events("breq", since=since)] == [True, False]
    rot = rig.c.coord(1)["rotary"]
    assert rot["full"] is True and rot["breq"] is False


def test_a_line_fits_only_while_used_plus_its_words_stay_within_the_size():
    rot = RotaryBuffer(1, 9, EventLog(simpy.Environment(), "c"), lambda: (5.0, 10.0),
                       SimpleNamespace(version=0))
    rot.used_words = 5
    assert rot.fits(4) and not rot.fits(5) and rot.free_words == 4


def test_executed_lines_give_their_words_back_as_execution_moves_past_them(rig):
    """A move starting frees every line before it, a non-motion line included."""
    rig.rotary_setup()
    rig.ok("&1 #1->X")
    rig.c.load_lines(1, ["TM100 X10", "P1=1", "X30"])
    words = {f["n"]: f["words"] for _, _, f in rig.events("line_loaded")}
    used: dict[int, int] = {}

    def sample(e) -> None:
        if e.type == "move_start":
            used.setdefault(e["n"], rig.c.coord(1)["rotary"]["used_words"])

    rig.c.log.listen(sample)
    rig.ok("&1 R")
    rig.run_for(1.0)
    assert used == {1: sum(words.values()), 3: words[3]}


def test_a_host_waiting_for_breq_is_woken_by_a_rise_never_by_a_fall(rig):
    """Each line loaded below I17 is a low→high pulse: an interrupt to the host (seed 000).
    A host waiting for it is woken once by the rise; a falling edge wakes nobody."""
    rig.rotary_setup()
    rot = rig.c.coord_system(1).rotary
    woken: list[str] = []
    rot.on_rise(lambda: woken.append("pulse"))
    rig.c.load_lines(1, ["X1"])
    assert woken == ["pulse"] and rot.breq is True
    rot.on_rise(lambda: woken.append("later"))
    rig.ok("I16=1")
    rig.ok("I17=1")
    rig.ok("OPEN ROT")  # 1 ahead = I17: BREQ falls and stays low
    rig.ok("CLOSE")
    assert rot.breq is False and woken == ["pulse"]


def test_i16_i17_of_the_configuration_hold_from_the_first_line(make_rig):
    rig = make_rig(i16=1, i17=2)
    rig.rotary_setup()
    rig.c.load_lines(1, ["X1", "X2"])
    rot = rig.c.coord(1)["rotary"]
    assert rot["full"] is True and rot["breq"] is False
