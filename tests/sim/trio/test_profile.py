"""Profile invariants over a grid of moves (spec §9.7 kinematics, SRAMP and MERGE as in
:mod:`motionsim.sim.trio.profile`): every profile covers exactly its length, position and speed are
continuous across segments, speed never goes negative nor above max(SPEED, v0), and it ends
at rest (or at ``v_end`` when merged)."""

from __future__ import annotations

import itertools

import pytest
from motionsim.sim.trio.motion.profile import plan, ramp_distance, ramp_time

LENGTHS = (0.5, 1.0, 10.0, 100.0)
V0S = (0.0, 300.0, 1000.0, 1500.0)
SRAMPS = (0.0, 0.002, 0.02)


@pytest.mark.parametrize(
    ("length", "v0", "ts", "stop"),
    list(itertools.product(LENGTHS, V0S, SRAMPS, (True, False))),
)
def test_profile_is_continuous_and_exact(length, v0, ts, stop):
    p = plan(length, 1000.0, 100_000.0, 50_000.0, sramp_s=ts, v0=v0, stop=stop)
    assert p.s(p.duration) == length
    assert p.s(p.duration * (1 - 1e-12)) == pytest.approx(length, abs=1e-6)
    for seg in p.segments[1:]:
        t = seg[0]
        assert p.s(t - 1e-12) == pytest.approx(seg[1], abs=1e-6)
        assert p.v(t - 1e-12) == pytest.approx(seg[2], abs=1e-3)
    top = max(1000.0, v0) + 1e-6
    steps = 200
    for i in range(steps):
        tau = p.duration * i / steps
        assert -1e-9 <= p.v(tau) <= top
        assert p.s(tau) <= p.s(p.duration * (i + 1) / steps) + 1e-9  # never runs backwards
    end_speed = p.segments[-1][2] + (p.duration - p.segments[-1][0]) * (
        p.segments[-1][3] + 0.5 * p.segments[-1][4] * (p.duration - p.segments[-1][0]))
    if stop:
        assert end_speed == pytest.approx(0.0, abs=1e-3)
    else:
        assert end_speed == pytest.approx(p.v_end, abs=1e-3)


def test_sramp_ramp_time_and_distance():
    """A ramp of dv at rate A with SRAMP Ts takes dv/A + Ts when dv >= A·Ts, else
    2·sqrt(dv·Ts/A); it covers the mean speed times that time."""
    assert ramp_time(1000.0, 1e5, 0.005) == pytest.approx(0.015)
    assert ramp_time(100.0, 1e5, 0.005) == pytest.approx(2 * (100 * 0.005 / 1e5) ** 0.5)
    assert ramp_time(1000.0, 1e5, 0.0) == pytest.approx(0.01)
    assert ramp_distance(0.0, 1000.0, 1e5, 0.005) == pytest.approx(7.5)
