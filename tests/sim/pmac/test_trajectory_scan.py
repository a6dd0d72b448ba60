"""The EPICS trajectory scan end to end (issue 24 item 3; spec §12.7): a host doing what
``pmacController.cpp`` does (examples/pmac/scan_host.py) against a PVT scan program of our own
written the way Diamond's is (examples/pmac/scan_program.pmc): double buffer in user memory,
M-variables re-pointed through their definition words, WHILE / IF / GOSUB, ``WL:`` of 48-bit floats.
Virtual time; the status variables and moves are asserted on the event log."""

from __future__ import annotations

from pathlib import Path

import pytest
from motionsim.examples.pmac.scan_host import ScanHost, points

PROGRAM = Path(__file__).parents[3] / "examples" / "pmac" / "scan_program.pmc"


def _load(rig) -> None:
    rig.ok("&1 #1->1000X #2->1000Y")
    for line in PROGRAM.read_text().splitlines():
        line = line.split(";")[0].strip()
        if line:
            rig.ok(line)


def _host(rig) -> ScanHost:
    host = ScanHost(ask=rig.ok)
    host.setup()
    return host


def _statuses(rig, since=0) -> list[tuple[int, float]]:
    return [(k, f["value"]) for k, _, f in rig.events("mvar", since=since)
            if f["name"] == "M4034"]


def test_tum_p246_trajectory_scan_completes_through_both_half_buffers(rig):
    _load(rig)
    host = _host(rig)
    assert (host.length, host.adr, host.version) == (50, (0xB850, 0xB850 + 19 * 50), 1.0)
    pts = points(120)
    since = rig.c.log.last_seq
    host.start(pts)
    while not rig.events("move_start", since=since):
        rig.c.env.step()
    t0 = rig.events("move_start", since=since)[0][0] * rig.period
    seen, at = set(), {}
    env = rig.c.env

    def sampler():  # the axes at each point's instant, whatever the host is doing
        for k in range(len(pts)):
            yield env.timeout(t0 + (k + 1) * 0.010 - env.now)
            at[k] = rig.c.positions(1)

    env.process(sampler())
    status = 1
    for _ in range(400):
        rig.run_for(0.05)
        status, _i, current, total = host.poll()
        seen.add(current)
        if status != 1:
            break
    assert status == 2 and total == 120  # one PVT move per point, the last one to rest
    assert seen == {0, 1}
    assert [v for _, v in _statuses(rig, since)] == [1, 2]
    assert ("fill", 1) in host.log and host.log.count(("fill", 0)) == 2
    # the motors followed the PVT points: at each point's instant the axes are there
    for k in range(len(pts)):
        assert at[k]["X"] == pytest.approx(pts[k].pos["X"], abs=1e-6), k
        assert at[k]["Y"] == pytest.approx(pts[k].pos["Y"], abs=1e-6), k
    assert float(rig.ok("#1P")) == pytest.approx(pts[-1].pos["X"] * 1000, abs=0.1)


def test_an_empty_half_after_a_full_one_ends_the_scan_at_its_last_point(rig):
    """Diamond's protocol (trajectory_scan_code.pmc, spec §12.7): when the program moves on
    from a full half to one whose fill is 0, the scan ends at the full half's last point, at
    rest — a scan whose points fill its last half exactly, or a host that has stopped
    filling; the host sees status 2 with fewer points done than it had."""
    _load(rig)
    host = _host(rig)
    pts = points(120)
    since = rig.c.log.last_seq
    host.start(pts)
    host.sent = len(pts)  # the host falls silent: half B is never filled
    rig.run_for(2.0)
    assert rig.ok("M4034 M4048 M4038") == "2\r0\r50"
    assert [v for _, v in _statuses(rig, since)] == [1, 2]
    assert rig.c.coord_system(1).state == "stopped"
    assert float(rig.ok("#1P")) == pytest.approx(pts[49].pos["X"] * 1000, abs=0.1)


def test_a_scan_filling_its_last_half_exactly_completes(rig):
    """100 points in halves of 50: the last half is full and the next one stays empty — the
    case that made the example host's default run end in an underrun."""
    _load(rig)
    host = _host(rig)
    pts = points(100)
    since = rig.c.log.last_seq
    host.start(pts)
    status = 1
    for _ in range(100):
        rig.run_for(0.05)
        status, _i, _c, total = host.poll()
        if status != 1:
            break
    assert (status, total) == (2, 100)
    assert [v for _, v in _statuses(rig, since)] == [1, 2]
    assert float(rig.ok("#1P")) == pytest.approx(pts[-1].pos["X"] * 1000, abs=0.1)


def test_abort_from_the_host_stops_the_scan(rig):
    _load(rig)
    host = _host(rig)
    host.start(points(120))
    rig.run_for(0.2)
    host.abort()
    rig.run_for(1.0)
    status, index, _c, total = host.poll()
    assert status == 2 and 0 < total < 60  # the loops end at the abort flag: idle, early
    assert rig.c.coord_system(1).state == "stopped"


def test_a_zero_move_time_is_the_programs_error_2(rig):
    _load(rig)
    host = _host(rig)
    pts = points(20)
    pts[5].time_us = 0
    host.start(pts)
    rig.run_for(3.0)
    assert rig.ok("M4034 M4048") == "3\r2"
