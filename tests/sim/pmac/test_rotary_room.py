"""Whether lines fit in a rotary buffer is decided once (``RotaryBuffer.fits``) and refused
once (``RotaryBuffer.no_room``: ERR006, the words free), whichever way the lines come: one
streamed line, a batch (all or nothing), or a line typed at the terminal into an open rotary
buffer (TSRM p46 ``DEFINE ROT``; ERR006 "buffer full")."""

from __future__ import annotations

import pytest
from motionsim.sim.errors import BufferFull


def _fill(rig) -> int:
    """Store ``X1`` lines until fewer than one more line's words are free; the line's words."""
    rig.rotary_setup(words=20)
    first = rig.c.load_lines(1, ["X1"])
    words = 20 - first.free_words
    while rig.c.coord(1)["rotary"]["free_words"] >= words:
        rig.c.load_lines(1, ["X1"])
    return words


def test_one_streamed_line_that_does_not_fit_is_err006_with_the_words_free(rig):
    words = _fill(rig)
    free = rig.c.coord(1)["rotary"]["free_words"]
    before = rig.c.coord(1)["rotary"]
    with pytest.raises(BufferFull) as exc:
        rig.c.load_lines(1, ["X1"])
    assert exc.value.pmac_error == "ERR006"
    assert exc.value.details["free_words"] == free
    assert str(exc.value) == f"line of {words} words does not fit ({free} words free)"
    assert rig.c.coord(1)["rotary"] == before  # nothing stored


def test_a_batch_that_does_not_fit_is_refused_whole_by_the_same_rule(rig):
    words = _fill(rig)
    free = rig.c.coord(1)["rotary"]["free_words"]
    before = rig.c.coord(1)["rotary"]
    with pytest.raises(BufferFull) as exc:
        rig.c.load_lines(1, ["X1", "X2"])
    assert exc.value.pmac_error == "ERR006"
    assert exc.value.details["free_words"] == free
    assert str(exc.value) == f"2 lines of {2 * words} words do not fit ({free} words free)"
    assert rig.c.coord(1)["rotary"] == before


def test_a_terminal_line_into_the_open_rotary_buffer_that_does_not_fit_is_err006(rig):
    rig.rotary_setup(words=3)
    rig.ok("&1 OPEN ROT")
    replies = [rig.cmd("X1") for _ in range(4)]  # one word each
    assert [r.error for r in replies] == [None, None, None, "ERR006"]
    assert rig.c.coord(1)["rotary"]["lines_ahead"] == 3  # the refused line is not stored
