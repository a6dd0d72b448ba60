"""Defining, opening, filling and deleting rotary buffers (seed 000, TUM p337, spec §1.1)."""

from __future__ import annotations

import pytest
from motionsim.sim.errors import BufferFull, Conflict, NotFound, ParseError


def test_the_manuals_define_rot_procedure_works(rig):
    """Seed 000: ``DELETE GATHER``, ``&3 DEFINE ROT 200``, ``&2 DEFINE ROT 1000``,
    ``&1 DEFINE ROT 20``."""
    rig.ok("DEFINE GATHER 1000")
    for line in ("DELETE GATHER", "&3 DEFINE ROT 200", "&2 DEFINE ROT 1000", "&1 DEFINE ROT 20"):
        rig.ok(line)
    assert [rig.c.rotary(cs)["size_words"] for cs in (1, 2, 3)] == [20, 1000, 200]


def test_define_rot_low_before_high_cs_is_err003(rig):
    """Seed 000: rotary buffers are defined from the highest-numbered CS down."""
    rig.ok("&1 DEFINE ROT 20")
    assert rig.cmd("&2 DEFINE ROT 20").error == "ERR003"
    assert rig.c.rotary(2) is None
    with pytest.raises(Conflict) as e:
        rig.c.define_rotary(3, 10)
    assert e.value.pmac_error == "ERR003"


def test_define_rot_with_a_gather_buffer_is_err003(rig):
    """Seed 000: there can be no data-gathering buffer at DEFINE ROT."""
    rig.ok("DEF GAT")
    assert rig.cmd("&1 DEF ROT 100").error == "ERR003"
    rig.ok("DEL GAT")
    rig.ok("&1 DEF ROT 100")


def test_delete_rot_frees_the_memory(rig):
    """PUM p213: DELETE ROT erases the buffer and de-allocates its memory."""
    free0 = int(rig.ok("SIZE"))
    rig.ok("&1 DEFINE ROT 600")
    assert int(rig.ok("SIZE")) == free0 - 600
    rig.ok("DELETE ROT")
    assert int(rig.ok("SIZE")) == free0
    assert rig.c.rotary(1) is None


def test_delete_rot_while_running_is_err001(rig):
    rig.rotary_setup()
    rig.ok("R")
    assert rig.cmd("DELETE ROT").error == "ERR001"


def test_size_is_negative_while_a_buffer_is_open(rig):
    """TSRM SIZE: negative if a buffer is currently open."""
    rig.rotary_setup()
    free = int(rig.ok("SIZE"))
    rig.ok("OPEN ROT")
    assert int(rig.ok("SIZE")) == -free


def test_words_are_one_per_command_word(rig):
    """Seed 000: each value takes one word (X1000 Y1200 Z1400 A1600 = 4 words); our rule for
    value-less words: one word each too."""
    rig.rotary_setup(words=600)
    r = rig.c.load_lines(1, ["X1000 Y1200 Z1400 A1600", "LINEAR INC", "P1=P2+3*4"])
    words = [f["words"] for _, _, f in rig.events("line_loaded")]
    assert words == [4, 2, 1]
    assert r.free_words == 600 - 7


def test_a_600_word_buffer_holds_150_four_axis_lines(rig):
    rig.rotary_setup(words=600)
    rig.c.load_lines(1, ["X1 Y2 Z3 A4"] * 150)
    with pytest.raises(BufferFull) as e:
        rig.c.load_lines(1, ["X1"])
    assert e.value.pmac_error == "ERR006"


def test_open_rot_sends_lines_to_the_addressed_cs(rig):
    """Seed 000 / PSRM OPEN ROT: lines go to the buffer of the CS addressed at each line."""
    rig.ok("&2 DEFINE ROT 100")
    rig.ok("&1 DEFINE ROT 100")
    rig.ok("OPEN ROT")
    rig.ok("&1 X10 Y10 F5 &2 X30 Y30 F10")
    got = [(f["cs"], f["text"]) for _, _, f in rig.events("line_loaded")]
    assert got == [(1, "X10 Y10 F5"), (2, "X30 Y30 F10")]


def test_load_lines_batch_is_atomic_on_a_parse_error(rig):
    """A bad line in a batch: ParseError with index and column; nothing stored, no edge."""
    rig.rotary_setup()
    since = rig.c.log.last_seq
    with pytest.raises(ParseError) as e:
        rig.c.load_lines(1, ["X1", "X2", "X3 @"])
    assert (e.value.index, e.value.column, e.value.text) == (2, 4, "X3 @")
    assert e.value.pmac_error == "ERR003"
    assert rig.c.log.read(since).events == []
    assert rig.c.rotary(1)["lines_ahead"] == 0


def test_load_lines_batch_that_does_not_fit_stores_nothing(rig):
    rig.rotary_setup(words=5)
    since = rig.c.log.last_seq
    with pytest.raises(BufferFull):
        rig.c.load_lines(1, ["X1 Y1", "X2 Y2", "X3 Y3"])
    assert rig.c.log.read(since).events == []


def test_load_lines_first_seq_is_idempotent(rig):
    """API.md: a line whose seq was already stored is acknowledged, not stored twice."""
    rig.rotary_setup()
    r1 = rig.c.load_lines(1, ["X1", "X2", "X3"], first_seq=10)
    r2 = rig.c.load_lines(1, ["X2", "X3", "X4", "X5"], first_seq=11)
    assert (r1.accepted, r1.stored) == (3, 3)
    assert (r2.accepted, r2.stored) == (4, 2)
    texts = [f["text"] for _, _, f in rig.events("line_loaded")]
    assert texts == ["X1", "X2", "X3", "X4", "X5"]
    r3 = rig.c.load_lines(1, ["X1", "X2"], first_seq=10)
    assert (r3.accepted, r3.stored, r3.lines_ahead) == (2, 0, 5)


def test_load_lines_without_rotary_is_not_found(rig):
    with pytest.raises(NotFound):
        rig.c.load_lines(1, ["X1"])
    with pytest.raises(NotFound):
        rig.c.coord(17)


def test_on_line_command_in_a_program_line_is_a_parse_error(rig):
    rig.rotary_setup()
    with pytest.raises(ParseError) as e:
        rig.c.load_lines(1, ["X1 R"])
    assert e.value.column == 4


def test_the_manuals_two_cs_open_rot_example_runs_both(rig):
    """PSRM OPEN ROTARY example: two rotary buffers filled and run with the buffers open."""
    for line in ("&2 DEFINE ROT 100", "&1 DEFINE ROT 100", "&1 B0 &2 B0", "OPEN ROT",
                 "&1 X10 Y10 F5", "&2 X30 Y30 F10", "&1R &2R"):
        rig.ok(line)
    rig.run_until_idle()
    ends = {(f["cs"], f["n"]) for _, _, f in rig.events("move_end")}
    assert ends == {(1, 1), (2, 1)}
    assert rig.c.positions(1) == {"X": 10.0, "Y": 10.0}
    assert rig.c.positions(2) == {"X": 30.0, "Y": 30.0}


def test_only_open_rot_opens_the_rotary_buffers(rig):
    """PSRM OPEN ROTARY: ``OPEN ROT`` opens the rotary buffers; ``OPEN PLC n`` opens a PLC
    buffer only, so the rotary buffer's ``open`` flag stays false and a program line typed
    meanwhile goes into the PLC, not into the rotary buffer."""
    rig.rotary_setup(words=100)
    assert rig.c.rotary(1)["open"] is False
    rig.ok("OPEN PLC 1")
    assert rig.c.rotary(1)["open"] is False
    assert int(rig.ok("SIZE")) < 0  # SIZE is negative while any buffer is open
    rig.ok("&2 &1")  # on-line addressing: no BREQ re-evaluation, the rotary buffer is closed
    rig.ok("P1=1")
    rig.ok("CLOSE")
    assert rig.c.rotary(1)["open"] is False
    assert rig.events("line_loaded", "breq") == []
    rig.ok("OPEN ROT")
    assert rig.c.rotary(1)["open"] is True
    rig.ok("CLOSE")
    assert rig.c.rotary(1)["open"] is False


@pytest.mark.parametrize("one_at_a_time", [True, False])
def test_a_line_that_exactly_fills_the_buffer_is_stored(rig, one_at_a_time):
    """A line fits while its words are at most the free words (ERR006 only beyond): the last
    two words of a 4-word buffer take a 2-word line, whether streamed one line per call (the
    streaming fast path) or in a batch; the next word is refused."""
    rig.rotary_setup(words=4)
    if one_at_a_time:
        rig.c.load_lines(1, ["X1 Y1"])
        r = rig.c.load_lines(1, ["X2 Y2"])
    else:
        r = rig.c.load_lines(1, ["X1 Y1", "X2 Y2"], first_seq=1)
    assert (r.free_words, rig.c.rotary(1)["lines_ahead"]) == (0, 2)
    with pytest.raises(BufferFull) as e:
        rig.c.load_lines(1, ["X3"])
    assert e.value.pmac_error == "ERR006"
    assert rig.c.rotary(1)["used_words"] == 4
