"""``first_seq``: numbered rotary batches are stored exactly once, and never dropped silently.

The rules are motionsim's (API.md "first_seq", sim/pmac/buffers/line_numbers.py): a resend of
exactly
the stored lines is acknowledged (idempotent); a gap, a repeat with a different text, or a
number out of range is refused with the expected next seq and changes nothing; DELETE ROT,
reset and ``A`` start the numbering again.
"""

from __future__ import annotations

import pytest
from motionsim.sim.errors import Conflict
from motionsim.sim.pmac.buffers.line_numbers import HISTORY, MAX_SEQ


def _texts(rig) -> list[str]:
    return [f["text"] for _, _, f in rig.events("line_loaded")]


def _refused(rig, lines, first_seq) -> Conflict:
    """The batch is refused and neither the log nor the buffer changed."""
    before_seq, before = rig.c.log.last_seq, rig.c.rotary(1)
    with pytest.raises(Conflict) as exc:
        rig.c.load_lines(1, lines, first_seq=first_seq)
    assert rig.c.log.last_seq == before_seq
    assert rig.c.rotary(1) == before
    return exc.value


def test_a_resend_of_exactly_the_stored_lines_is_acknowledged_not_stored_again(rig):
    rig.rotary_setup()
    rig.c.load_lines(1, ["X1", "X2", "X3"], first_seq=1)
    again = rig.c.load_lines(1, ["X1", "X2", "X3"], first_seq=1)
    assert (again.accepted, again.stored, again.lines_ahead) == (3, 0, 3)
    overlap = rig.c.load_lines(1, ["X3", "X4"], first_seq=3)
    assert (overlap.accepted, overlap.stored) == (2, 1)
    assert _texts(rig) == ["X1", "X2", "X3", "X4"]


def test_last_seq_never_goes_backwards_a_late_duplicate_then_a_resend_stores_once(rig):
    """A late duplicate of batch 1 arrives after batch 2; the host then resends batch 2."""
    rig.rotary_setup()
    rig.c.load_lines(1, ["X1", "X2", "X3"], first_seq=1)
    rig.c.load_lines(1, ["X4", "X5", "X6"], first_seq=4)
    late = rig.c.load_lines(1, ["X1", "X2", "X3"], first_seq=1)
    resend = rig.c.load_lines(1, ["X4", "X5", "X6"], first_seq=4)
    assert (late.stored, resend.stored) == (0, 0)
    assert _texts(rig) == ["X1", "X2", "X3", "X4", "X5", "X6"]
    nxt = rig.c.load_lines(1, ["X7"], first_seq=7)
    assert nxt.stored == 1


def test_a_gap_is_409_with_the_expected_next_seq(rig):
    rig.rotary_setup()
    rig.c.load_lines(1, ["X1", "X2"], first_seq=1)
    err = _refused(rig, ["X5"], 5)
    assert (err.code, err.details["reason"], err.details["expected_seq"]) == (
        "conflict", "gap", 3)
    assert "lines 3..4 were never stored" in err.message


def test_an_overlap_with_a_different_text_is_409_naming_the_line(rig):
    rig.rotary_setup()
    rig.c.load_lines(1, ["X1", "X2", "X3"], first_seq=1)
    err = _refused(rig, ["X2", "X9", "X4"], 2)
    assert (err.details["reason"], err.details["expected_seq"], err.details["index"]) == (
        "overlap_mismatch", 4, 1)
    assert "line 3 was stored as 'X3', not 'X9'" in err.message


def test_one_batch_numbered_two_to_the_63_is_refused_and_later_batches_still_store(rig):
    rig.rotary_setup()
    rig.c.load_lines(1, ["X1"], first_seq=1)
    err = _refused(rig, ["X2"], 2**63)
    assert (err.details["reason"], err.details["expected_seq"]) == ("out_of_range", 2)
    _refused(rig, ["X2", "X3"], MAX_SEQ)  # its last line would be MAX_SEQ + 1
    assert rig.c.load_lines(1, ["X2"], first_seq=2).stored == 1
    assert _texts(rig) == ["X1", "X2"]


def test_a_repeat_older_than_the_texts_kept_is_refused_not_assumed(rig):
    rig.rotary_setup(words=HISTORY + 100)
    rig.c.load_lines(1, [f"X{i}" for i in range(1, HISTORY + 11)], first_seq=1)
    err = _refused(rig, ["X1", "X2"], 1)
    assert (err.details["reason"], err.details["expected_seq"]) == (
        "overlap_too_old", HISTORY + 11)


def test_a_host_renumbering_from_one_after_abort_is_stored(rig):
    rig.rotary_setup()
    rig.c.load_lines(1, ["X1", "X2"], first_seq=1)
    _refused(rig, ["X10"], 1)  # without abort: a renumbered batch is a mismatch
    rig.ok("&1 A")
    assert rig.c.load_lines(1, ["X10"], first_seq=1).stored == 1
    assert _texts(rig) == ["X1", "X2", "X10"]


def test_delete_rot_and_reset_start_the_numbering_again(rig):
    rig.rotary_setup()
    rig.c.load_lines(1, ["X1", "X2"], first_seq=1)
    rig.ok("&1 DELETE ROT")
    rig.ok("&1 DEFINE ROT 100")
    assert rig.c.load_lines(1, ["X7"], first_seq=1).stored == 1
    rig.c.reset()
    rig.ok("&1 DEFINE ROT 100")
    assert rig.c.load_lines(1, ["X8"], first_seq=1).stored == 1


def test_unnumbered_lines_do_not_move_the_expected_seq(rig):
    rig.rotary_setup()
    rig.c.load_lines(1, ["X1"], first_seq=1)
    rig.c.load_lines(1, ["X2", "X3"])
    assert rig.c.load_lines(1, ["X4"], first_seq=2).stored == 1
    assert _refused(rig, ["X4"], 4).details["expected_seq"] == 3


def test_a_line_longer_than_the_card_holds_is_err003_and_nothing_is_kept(rig):
    """255 characters at most; a refused line is neither stored nor cached."""
    from motionsim.sim.errors import BufferFull, ParseError
    from motionsim.sim.pmac import controller as pmac_controller

    rig.rotary_setup(words=10)
    longest = "X1" + " " * 253
    assert rig.c.load_lines(1, [longest]).stored == 1
    huge = "X1 " * 400_000
    with pytest.raises(ParseError) as exc:
        rig.c.load_lines(1, ["X2", huge])
    assert (exc.value.index, exc.value.column, exc.value.pmac_error) == (1, 256, "ERR003")
    assert len(exc.value.text) < 100
    with pytest.raises(BufferFull):  # 20 words do not fit in the 10
        rig.c.load_lines(1, [f"X{i} Y{i}" for i in range(10, 20)])
    cache = pmac_controller._LINE_CACHE
    assert huge not in cache and not any(f"X{i} Y{i}" in cache for i in range(10, 20))
    assert _texts(rig) == [longest]
