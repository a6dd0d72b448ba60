"""The PVT trajectory-scan and velocity-limited LINEAR examples (examples/pmac/) run and show
what their READMEs say: every PVT segment executed back to back under BREQ with no run-time
error, and Ixx16 stretching exactly the moves that ask too much of a motor (TSRM p98)."""

from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[3] / "examples" / "pmac"


def _load(name: str):
    spec = importlib.util.spec_from_file_location(name, EXAMPLES / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)  # type: ignore[union-attr]
    return mod


def test_pvt_trajectory_scan_streams_every_segment_back_to_back_under_breq(tmp_path):
    ex = _load("pvt_trajectory_scan")
    c, program = ex.run()
    starts, ends = c.log.events("move_start"), c.log.events("move_end")
    assert len(ends) == ex.POINTS == len(program) - 1
    assert all("error" not in e.fields for e in c.log.events("program"))
    # segments abut: the whole scan takes POINTS x SEGMENT_MS to the servo cycle
    period = c.scheduler.period_s
    total = ends[-1].t - starts[0].t
    assert abs(total - ex.POINTS * ex.SEGMENT_MS / 1000) <= period
    x, _, y, _ = ex.path(0.5)
    samples = dict(c.samples)
    t = starts[0].t + 0.5
    near = min(samples, key=lambda s: abs(s - t))
    assert samples[near]["X"] == pytest.approx(x, abs=0.5)
    assert samples[near]["Y"] == pytest.approx(y, abs=0.5)
    out = tmp_path / "scan.png"
    ex.plot(c, str(out))
    assert out.stat().st_size > 10_000


def test_velocity_limited_linear_stretches_only_the_moves_over_ixx16():
    ex = _load("velocity_limited_linear")
    slow, fast = ex.durations(ex.run(32)[0]), ex.durations(ex.run(1000)[0])
    assert slow[2] == pytest.approx(fast[2], abs=1e-3)  # 4 units in 200 ms: 20 cts/ms
    assert slow[3] == pytest.approx(0.250, abs=1e-3)  # 8000 cts at 32 cts/ms
    assert fast[3] == pytest.approx(0.200, abs=1e-3)
    assert slow[4] == pytest.approx(0.250, abs=1e-3)  # Y 8 units: Y's motor limits


def test_velocity_limited_linear_at_the_factory_ixx17_makes_every_move_a_triangle():
    """PSRM p74 / TUM p276: at Ixx17 = 0.015625 counts/ms² each TM200 move is calculated as
    if it were the last; X4 (4000 counts) from rest takes sqrt(4000 / 0.015625) = 506 ms."""
    ex = _load("velocity_limited_linear")
    d = ex.durations(ex.run(32, 0.015625)[0])
    assert d[2] == pytest.approx(math.sqrt(4000 / 0.015625) / 1000, abs=1e-3)
    assert all(d[n] > 0.4 for n in (2, 3, 4, 5))


def test_gather_blended_corner_records_the_rounded_commanded_path(tmp_path):
    """examples/pmac/gather_blended_corner.py: the card's data gathering (TSRM p170-171) of
    motors 1 and 2's commanded positions every servo cycle, read back with LIST GATHER as a
    host decodes it. X10 then Y10, TM200 TA100: the second move starts blending (its
    ``move_start``) 100 ms before the first would stop, while X decelerates over the last
    v·TA/2 = 0.05 units/ms · 100 ms / 2 = 2.5 units (TUM p217), so the path leaves the X
    axis at X = 7.5 and never reaches the corner."""
    ex = _load("gather_blended_corner")
    c, path = ex.run()
    rec = c.recording()
    period = c.scheduler.period_s
    started = next(e for e in c.log.events("gather") if e["state"] == "started")
    assert rec.cycles == tuple(range(round(started.t / period) + 1,
                                     round(started.t / period) + 1 + len(path)))
    assert [(x, y) for x, y in path] == [
        (x / (1000 * 96 * 32), y / (1000 * 96 * 32)) for x, y in zip(*rec.columns, strict=True)]
    at = dict(zip(rec.cycles, path, strict=True))
    blend = round(next(e for e in c.log.events("move_start") if e["n"] == 3).t / period)
    end = round(next(e for e in c.log.events("move_end") if e["n"] == 3).t / period)
    assert at[blend] == (pytest.approx(7.5, abs=0.01), 0.0)
    assert all(y == 0.0 for k, (_, y) in at.items() if k <= blend)
    assert at[end] == (10.0, 10.0)
    assert ex.closest_to_corner(path) > 0.5
    out = tmp_path / "corner.png"
    ex.main(str(out))
    assert out.stat().st_size > 0
