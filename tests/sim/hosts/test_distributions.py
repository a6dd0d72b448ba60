"""Seeded delay distributions: right shape, never negative, reproducible."""

from __future__ import annotations

import random
import statistics

import pytest
from motionsim.sim.hosts.distributions import Delay, empirical, fixed


def draws(d: Delay, n: int = 4000, seed: int = 1) -> list[float]:
    rng = random.Random(seed)
    return [d.draw(rng) for _ in range(n)]


def test_fixed_is_constant():
    assert set(draws(fixed(0.002), 10)) == {0.002}


def test_uniform_stays_in_range():
    xs = draws(Delay("uniform", 0.001, 0.003))
    assert min(xs) >= 0.001 and max(xs) <= 0.003
    assert statistics.mean(xs) == pytest.approx(0.002, rel=0.05)


def test_normal_is_clamped_at_zero():
    xs = draws(Delay("normal", 0.001, 0.003))
    assert min(xs) == 0.0
    assert all(x >= 0 for x in xs)


def test_lognormal_median():
    xs = draws(Delay("lognormal", 0.002, 0.5))
    assert statistics.median(xs) == pytest.approx(0.002, rel=0.1)


def test_jitter_is_plus_minus():
    xs = draws(Delay("fixed", 0.002, jitter_s=0.001))
    assert 0.001 <= min(xs) < 0.0012 and 0.0028 < max(xs) <= 0.003


def test_empirical_resamples():
    assert set(draws(empirical([0.001, 0.004]), 100)) == {0.001, 0.004}


def test_same_seed_same_draws():
    d = Delay("normal", 0.002, 0.001, jitter_s=0.0005)
    assert draws(d, 50, seed=9) == draws(d, 50, seed=9)
    assert draws(d, 50, seed=9) != draws(d, 50, seed=10)


@pytest.mark.parametrize(
    "kw",
    [
        {"kind": "fixed", "a": -1.0},
        {"kind": "uniform", "a": 2.0, "b": 1.0},
        {"kind": "lognormal", "a": 0.0, "b": 1.0},
        {"kind": "empirical"},
        {"kind": "gamma", "a": 1.0},
        {"kind": "fixed", "a": 1.0, "jitter_s": -0.1},
    ],
)
def test_impossible_distributions_are_refused(kw):
    with pytest.raises(ValueError):
        Delay(**kw)
