"""The example programs of ``examples/trio/`` that users write, run on a simulated MC206 with
their motion asserted on the event log (issue: pick-and-place, gearing/cam, continuous path)."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from tests.sim.trio.conftest import cycle, fields, make, run_to

EXAMPLES = Path(__file__).resolve().parents[3] / "examples" / "trio"


def _load(c, name: str, process: int = 1) -> None:
    c.store_program(name.upper(), (EXAMPLES / f"{name}.bas").read_text())
    c.run_program(name.upper(), process)


def _runs(c, axis: int) -> list[tuple[float, float]]:
    starts = [t for t, _ in fields(c, "move_start", axis=axis)]
    ends = [t for t, _ in fields(c, "move_end", axis=axis)]
    return list(zip(starts, ends, strict=True))


def test_pick_and_place_moves_each_part_and_reports_it():
    """MOVEABS / WAIT IDLE / IF / GOSUB: per part two X moves (pick, drop) and four Z moves
    (down, up, down, up), never overlapping; even parts drop at VR(2), odd at VR(3)."""
    c = make()
    for i, v in enumerate((4, 100, 300, 250)):
        c.set_variable(f"VR({i})", v)
    _load(c, "pick_and_place")
    run_to(c, 20.0)
    x, z = _runs(c, 0), _runs(c, 1)
    assert len(x) == 4 * 2 + 1 and len(z) == 4 * 4 + 1  # + the final MOVEABS(0,0)
    # the program waits for each move: the next one (any axis) starts after it ended
    timeline = sorted([*x[:-1], *z[:-1]])
    assert all(b[0] > a[1] for a, b in zip(timeline, timeline[1:], strict=False))
    assert [f["text"] for _, f in fields(c, "print")] == [
        "placed part 1 at 250", "placed part 2 at 300", "placed part 3 at 250",
        "placed part 4 at 300",
    ]
    assert c.get_variable("VR(10)") == 4.0
    assert (c.axis(0)["dpos"], c.axis(1)["dpos"]) == (0.0, 0.0)
    assert c.processes()[0]["state"] == "stopped" and "error" not in c.processes()[0]


def test_gearing_cam_roller_cutter_and_cam_follow_the_conveyor():
    """CONNECT 1:2, CAMBOX over 200 units of conveyor travel, then CAM in time."""
    c = make()
    _load(c, "gearing_cam")
    run_to(c, 2.0)
    assert [f["mtype"] for _, f in fields(c, "move_start", axis=1)] == [21]
    assert [f["mtype"] for _, f in fields(c, "move_start", axis=2)] == [20]
    assert [f["mtype"] for _, f in fields(c, "move_start", axis=3)] == [13]
    (conveyor,) = _runs(c, 0)
    (cutter,) = _runs(c, 2)
    # the links were loaded before the conveyor started; the cutter's CAMBOX ends half-way
    assert _runs(c, 1)[0][0] < cutter[0] < conveyor[0] < cutter[1] < conveyor[1]
    assert cycle(c, cutter[1]) - cycle(c, conveyor[0]) == 205  # 200 units: 10 ms ramp + 195
    assert [f["text"] for _, f in fields(c, "print")] == ["roller 200.0 cutter 100.0 cam 100.0"]


def test_cp_feeder_keeps_ntype_full_and_never_stops_the_path():
    """Every move after the first takes over MTYPE in the servo period its predecessor ends
    (NTYPE was full and MERGE runs them into each other at speed: MTYPE never reads 0 at a
    joint), and the program never waits."""
    c = make()
    pts = [(100, 0), (200, 20), (300, 0), (400, 20), (500, 0), (600, 20)]
    c.set_variable("VR(0)", len(pts))
    for i, (x, y) in enumerate(pts):
        c.set_variable(f"VR({100 + 2 * i})", x)
        c.set_variable(f"VR({101 + 2 * i})", y)
    _load(c, "cp_feeder")
    run_to(c, 2.0)
    runs = _runs(c, 0)
    assert len(runs) == len(pts)
    gaps = [cycle(c, b[0]) - cycle(c, a[1]) for a, b in zip(runs, runs[1:], strict=False)]
    assert gaps == [0] * (len(pts) - 1)
    assert "blocked" not in {f["state"] for _, f in fields(c, "process", process=1)}
    assert c.get_variable("VR(1)") > 0  # it did other work meanwhile
    assert (c.axis(0)["dpos"], c.axis(1)["dpos"]) == pytest.approx((600.0, 20.0))
    # MERGE: one ramp up and one down for the whole path (the moves run into each other at
    # SPEED), so it takes about its length at 1000 units/s plus 10 ms, not 10 ms more per move
    path = sum(math.dist(p, q) for p, q in zip([(0, 0), *pts], pts, strict=False))
    periods = cycle(c, runs[-1][1]) - cycle(c, runs[0][0])
    assert periods == pytest.approx(path + 10, abs=3)


@pytest.mark.parametrize(("name", "axis", "moves", "text"), [
    ("pick_and_place", 0, 4 * 2 + 1, "no VR inputs: demonstration with 4 parts"),
    ("cp_feeder", 0, 8, "no VR inputs: demonstration path of 8 points"),
])
def test_with_no_vr_inputs_the_example_runs_its_demonstration(name, axis, moves, text):
    """Issue 36 item 5: on a fresh controller (every VR 0) these did nothing; they now say
    so and run a demonstration with the inputs their header names."""
    c = make()
    _load(c, name)
    run_to(c, 20.0)
    assert [f["text"] for _, f in fields(c, "print")][0] == text
    assert len(_runs(c, axis)) == moves
    assert "error" not in c.processes()[0]
