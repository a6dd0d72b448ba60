"""``examples/pmac/spline_points.py`` shows what its docstring says (TUM p290): the SPLINE1
run takes (N + 2)·T and passes through the way-points, not the programmed points."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

EXAMPLE = Path(__file__).resolve().parents[3] / "examples" / "pmac" / "spline_points.py"


def _load():
    spec = importlib.util.spec_from_file_location("spline_points", EXAMPLE)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)  # type: ignore[union-attr]
    return mod


def test_spline_points_example_takes_n_plus_2_segments_through_the_way_points(tmp_path):
    ex = _load()
    c, samples = ex.run("SPLINE1")
    period = c.scheduler.period_s
    n = len(ex.POINTS)
    assert ex.duration(c) == pytest.approx((n + 2) * ex.SEGMENT_MS / 1000, abs=period)
    assert all("error" not in e.fields for e in c.log.events("program"))
    # 300 ms in (the added segment, then point 1's): the boundary of point (10, 10) is its
    # way-point (P1 + 4·P2 + P3) / 6 = (11.67, 8.33), inside the corner, not the point
    t0 = c.log.events("move_start")[0].t
    t, x, y = min(samples, key=lambda s: abs(s[0] - (t0 + 0.3)))
    pts = [(0, 0), *ex.POINTS]
    wp = [(pts[1][k] + 4 * pts[2][k] + pts[3][k]) / 6 for k in (0, 1)]
    speed = 10 / 0.1  # at most one segment's distance per segment time (units/s)
    assert x == pytest.approx(wp[0], abs=speed * abs(t - t0 - 0.3) + 1e-6)
    assert y == pytest.approx(wp[1], abs=speed * abs(t - t0 - 0.3) + 1e-6)
    assert (x, y) != pytest.approx((10, 10), abs=1.0)
    linear, _ = ex.run("LINEAR")
    assert ex.duration(linear) < ex.duration(c)
    out = tmp_path / "spline.png"
    ex.main(str(out))
    assert out.stat().st_size > 10_000
