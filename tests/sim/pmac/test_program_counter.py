"""``PC`` / ``PE``: the program and line offset the addressed CS's program counter points to
(the line calculated next) and of the move executing, for fixed PROGs and the rotary buffer
(sim/pmac/buffers/program_counter.py; reply ``P{prog}:{offset}`` [BK])."""

from __future__ import annotations

import pytest
from motionsim.sim.pmac.host.listing import entries

from tests.sim.pmac.test_fixed_programs import load as load_prog

# word offsets as LIST PROG 3,0 numbers them: TM100 (1 word) at 0, X10 at 1, X20 at 2, ...
PROG = ["TM100", "X10", "X20", "X30"]


def load(rig, n: int = 3, lines=PROG) -> None:
    load_prog(rig, n, lines)


def offsets(lines=PROG) -> list[int]:
    return [off for off, _ in entries(lines)]  # the listing's offsets, the closing RET last


def test_pc_after_b_points_at_the_top_of_the_program(rig):
    load(rig)
    rig.ok("&1 B3")
    assert rig.ok("&1 PC") == "P3:0"
    assert rig.ok("&1PE") == "P3:0"  # nothing executing: where the counter points [INF]


def test_pc_uses_the_word_offsets_of_list_prog(rig):
    load(rig)
    listing = rig.ok("LIST PROG 3,0")
    assert listing.split("\r") == ["0:TM100", "1:X10", "2:X20", "3:X30", "4:RET"]
    assert offsets() == [0, 1, 2, 3, 4]


def test_pe_reports_the_executing_move_and_pc_the_line_calculated_next(rig):
    load(rig)
    rig.ok("&1 B3 R")
    # run until the first move (line 2, X10) executes
    while not rig.events("move_start"):
        rig.c.env.step()
    n = rig.events("move_start")[-1][2]["n"]
    assert n == 2
    assert rig.ok("&1PE") == "P3:1"  # X10 is at word offset 1
    pc = rig.ok("&1PC")
    calculated = [e["n"] for _, _, e in rig.events("line_calculated")]
    nxt = max(calculated) + 1  # the line not yet calculated
    assert pc == f"P3:{offsets()[nxt - 1]}"
    assert pc != "P3:1"  # the program counter runs ahead of the executing move


def test_pc_at_the_end_of_a_fixed_program_points_at_its_ret(rig):
    load(rig)
    rig.ok("&1 B3 R")
    rig.run_until_idle()
    assert rig.c.coord(1)["program"]["state"] == "stopped"
    assert rig.ok("&1PC") == "P3:4"  # the RET the card adds after X30
    assert rig.ok("&1PE") == "P3:4"
    rig.ok("&1B3")
    assert rig.ok("&1PC") == "P3:0"  # B points it at the top again


def test_pc_of_the_rotary_buffer_is_program_0(rig):
    rig.rotary_setup()
    port = rig.c.open_port("host")
    rig.ok("OPEN ROT", port)
    for line in ["TM100", "X10", "X20"]:
        rig.ok(line, port)
    assert rig.ok("&1PC", port) == "P0:0"  # buffers open: PC still acts on-line
    rig.ok("CLOSE", port)
    rig.ok("&1R")
    rig.run_until_idle()
    assert rig.c.coord(1)["program"]["state"] == "waiting"
    # all three lines calculated: the counter waits at the next line to be stored
    assert rig.ok("&1PC") == "P0:3"


def test_pc_and_pe_follow_the_addressed_coordinate_system(rig):
    load(rig)
    load(rig, 9, ["TM50", "X1"])
    rig.ok("&1B3&2B9")
    assert rig.ok("&1PC&2PC") == "P3:0\rP9:0"


def test_pc_of_a_cs_pointing_at_no_program_is_err003(rig):
    reply = rig.cmd("&1PC")
    assert reply.error is not None and "ERR003" in str(reply.error)


def test_pe_of_the_rotary_buffer_is_the_executing_moves_line(rig):
    rig.rotary_setup()
    port = rig.c.open_port("host")
    rig.ok("OPEN ROT", port)
    for line in ["TM100", "X10", "X20", "X30"]:
        rig.ok(line, port)
    rig.ok("CLOSE", port)
    rig.ok("&1R")
    while not rig.events("move_start"):
        rig.c.env.step()
    assert rig.events("move_start")[-1][2]["n"] == 2
    assert rig.ok("&1PE") == "P0:1"  # line 2, the buffer's second line


def test_pc_polled_and_list_prog_read_in_windows_decompile_a_large_program_once(
        rig, monkeypatch):
    """A host polls ``PC`` and reads a program back in windows (``LIST PROG n,start,len``,
    as dls-pmacanalyse does): the program's listing offsets are worked out once while it
    does not change, not once per poll or window — 3 000 lines take 40 ms each time, on the
    event loop."""
    from motionsim.sim.pmac.host import listing

    lines = [f"X{i} P{i % 900}=P{i % 900}+{i}" for i in range(3000)]
    load(rig, 3, lines)
    rig.ok("&1 B3")
    assert rig.ok("&1 PC") == "P3:0"
    first = rig.ok("LIST PROG 3,0,40").split("\r")
    calls: list[str] = []
    canonical = listing.canonical
    monkeypatch.setattr(listing, "canonical", lambda text: calls.append(text) or canonical(text))
    windows = [rig.ok(f"LIST PROG 3,{start},40").split("\r") for start in (0, 40, 80)]
    polls = [rig.ok("&1 PC") for _ in range(3)]
    assert not calls, len(calls)
    assert windows[0] == first and polls == ["P3:0"] * 3
    every = [f"{off}:{text}" for off, text in entries(lines)]
    assert windows == [[e for e in every if start <= int(e.split(":")[0]) < start + 40]
                       for start in (0, 40, 80)]


def test_pe_follows_the_executing_move_into_a_called_program(rig):
    """TSRM p416 CALL: the moves of PROG 7 run inside PROG 3; while one of them executes
    ``PE`` names PROG 7 and that line's offset, and after the RETURN PROG 3 again."""
    load(rig, 7, ["X15", "X16"])  # offsets 0, 1 (RET 2)
    load(rig, 3, ["TM200", "X10", "CALL7", "X30"])  # offsets 0, 1, 2, 3
    rig.ok("&1 B3 R")
    seen: list[tuple[int, str]] = []
    done = 0
    while done < 4:
        rig.c.env.step()
        starts = rig.events("move_start")
        if len(starts) > done:
            done = len(starts)
            seen.append((starts[-1][2]["n"], rig.ok("&1PE")))
    assert seen == [(2, "P3:1"), (1, "P7:0"), (2, "P7:1"), (4, "P3:3")]


@pytest.mark.parametrize("texts", [("X1",), ("X1", "X2 Y3"), ("X1", "X2 Y3", "DWELL10")])
def test_a_line_past_the_end_is_the_closing_ret(texts):
    """``line_offset`` of any line past the last is the word of the card's closing RET,
    one word after the last line's words (the listing's stored offsets)."""
    from motionsim.sim.pmac.host import listing
    from motionsim.sim.pmac.host.program_counter import line_offset

    offsets = listing.stored_offsets(texts)
    assert [line_offset(texts, n) for n in range(1, len(texts) + 1)] == list(offsets[:-1])
    for n in (len(texts) + 1, len(texts) + 2, len(texts) + 9):
        assert line_offset(texts, n) == offsets[-1]
