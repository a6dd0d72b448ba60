"""``first_seq`` range (API.md "first_seq"; :mod:`motionsim.sim.pmac.buffers.line_numbers`):
a batch's *last* line must be numbered at most ``MAX_SEQ`` — checked on the first numbered
batch too, where no gap rule could refuse it instead. Found by ``make mutate``: the range
check of the last line number was not pinned."""

from __future__ import annotations

import pytest
from motionsim.sim.errors import Conflict
from motionsim.sim.pmac.buffers.line_numbers import MAX_SEQ


def test_a_first_batch_ending_exactly_at_max_seq_is_stored(rig):
    rig.rotary_setup()
    result = rig.c.load_lines(1, ["X1", "X2"], first_seq=MAX_SEQ - 1)
    assert result.stored == 2
    numbered = rig.c.coord_system(1).rotary.numbering
    assert numbered.last_seq == MAX_SEQ


def test_a_first_batch_whose_last_line_passes_max_seq_is_refused_out_of_range(rig):
    rig.rotary_setup()
    before = rig.c.rotary(1)
    with pytest.raises(Conflict) as exc:
        rig.c.load_lines(1, ["X1", "X2"], first_seq=MAX_SEQ)
    assert exc.value.details["reason"] == "out_of_range"
    assert f"{MAX_SEQ}..{MAX_SEQ + 1}" in exc.value.message
    assert rig.c.rotary(1) == before
