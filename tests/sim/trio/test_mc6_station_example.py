"""The MC6xx example (issue 32: programs written as MC4xx / MC6xx programs are): a BASIC
library ``examples/trio/mc6_machine.bal`` and a station program ``mc6_station.bas`` using it —
CONSTANT lines, DIM with initial values and several names, a two-dimensional table, an EtherCAT
start-up poll, a SELECT_CASE state machine left with EXIT_LOOP, shifts in the library's status
word — run on model ``mc6xx`` in virtual time, and passing ``motionsim check``."""

from __future__ import annotations

from pathlib import Path

from motionsim.app.check import check_file

from tests.sim.trio.conftest import fields, make, run_to

EXAMPLES = Path(__file__).resolve().parents[3] / "examples" / "trio"
LIBRARY, PROGRAM = EXAMPLES / "mc6_machine.bal", EXAMPLES / "mc6_station.bas"


def _station():
    c = make(model="mc6xx", axes=4)
    c.store_program("MC6_MACHINE", LIBRARY.read_text())
    c.store_program("MC6_STATION", PROGRAM.read_text())
    for i, v in enumerate((10, 20, 30, 100)):  # station distances; 100 is clamped to 90
        c.set_variable(f"VR({11 + i})", v)
    for i in (20, 21, 22):  # three slots of a table taken: the first free one is 3
        c.set_variable(f"VR({i})", 1)
    c.run_program("MC6_STATION", 1)
    return c


def test_the_station_program_indexes_four_stations_and_reports():
    c = _station()
    run_to(c, 5.0)
    (_t, last), = fields(c, "process", process=1, state="stopped")
    assert "error" not in last
    assert c.unread_output("t") == ["EtherCAT OP with 4.0000 slaves", "done at 150.0"]
    assert c.vr[59:63] == [3.0, 0.0, 150.0, 3.0]  # bus OP; idle status; 15000 counts = 150 mm
    starts = [t for t, _ in fields(c, "move_start", axis=0)]
    ends = [t for t, _ in fields(c, "move_end", axis=0)]
    assert len(starts) == len(ends) == 4
    assert all(s > e for s, e in zip(starts[1:], ends, strict=False))  # WAIT IDLE between
    assert c.axis(0)["dpos"] == 150.0


def test_the_status_word_an_hmi_reads_while_the_station_runs():
    """status_word(TRUE, 2, FALSE) = bit 0 | 2 << 4 = 33, written after the second move."""
    c = _station()
    second_end = None
    while second_end is None:
        run_to(c, c.env.now + 0.01)
        ends = [t for t, _ in fields(c, "move_end", axis=0)]
        second_end = ends[1] if len(ends) > 1 else None
    run_to(c, second_end + 0.002)
    assert c.get_variable("VR(60)") == 33.0


def test_the_example_passes_the_check_tool():
    assert check_file(PROGRAM, model="mc6xx", siblings=[PROGRAM, LIBRARY]) == []
    assert check_file(LIBRARY, model="mc6xx") == []
