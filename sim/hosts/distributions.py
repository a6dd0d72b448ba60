"""Latency and jitter distributions for host models, drawn from a seeded ``random.Random``.

A host's answer to a BREQ interrupt, a ``PR`` round trip or a write over the link does not take
a fixed time: the PC's interrupt latency, the OS scheduler and the bus add jitter. A scenario
describes that delay as one of these distributions (all in seconds here; the scenario file uses
milliseconds). Draws come from the host's own ``random.Random(seed)``, so the same seed gives the
same delays and the same event log, byte for byte, on any machine (the stdlib generator is
specified; numpy is deliberately not used in ``sim/``).

Every distribution may add ``jitter_s``: a uniform term in ``[-jitter_s, +jitter_s]`` ("2 ms ±
3 ms"). A delay is never negative: draws below zero are clamped to zero (a host cannot answer
before it is asked).
"""

from __future__ import annotations

import math
import random
from collections.abc import Sequence
from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class Delay:
    """A non-negative random delay in seconds.

    Args:
        kind: ``fixed`` (``a`` = value), ``uniform`` (``a``..``b``), ``normal`` (mean ``a``,
            standard deviation ``b``), ``lognormal`` (median ``a``, shape sigma ``b``) or
            ``empirical`` (uniform choice among ``values``).
        a, b: the kind's parameters, seconds (sigma of ``lognormal`` is dimensionless).
        values: the samples of an ``empirical`` distribution, seconds.
        jitter_s: half-width of a uniform jitter added to every draw.
    """

    kind: str = "fixed"
    a: float = 0.0
    b: float = 0.0
    values: tuple[float, ...] = ()
    jitter_s: float = 0.0

    def __post_init__(self) -> None:
        if self.kind not in _KINDS:
            raise ValueError(f"unknown distribution {self.kind!r}; one of {', '.join(_KINDS)}")
        numbers = (self.a, self.b, self.jitter_s, *self.values)
        if any(not math.isfinite(x) or x < 0 for x in numbers):
            raise ValueError("delays, spreads and jitter must be finite and >= 0")
        if self.kind == "uniform" and self.b < self.a:
            raise ValueError("uniform: high must be >= low")
        if self.kind == "lognormal" and self.a <= 0:
            raise ValueError("lognormal: median must be > 0")
        if self.kind == "empirical" and not self.values:
            raise ValueError("empirical: needs at least one sample")

    def draw(self, rng: random.Random) -> float:
        """One delay, seconds, >= 0."""
        kind = self.kind
        if kind == "fixed":
            x = self.a
        elif kind == "uniform":
            x = rng.uniform(self.a, self.b)
        elif kind == "normal":
            x = rng.gauss(self.a, self.b) if self.b > 0 else self.a
        elif kind == "lognormal":
            x = rng.lognormvariate(math.log(self.a), self.b)
        else:
            x = self.values[rng.randrange(len(self.values))]
        if self.jitter_s > 0:
            x += rng.uniform(-self.jitter_s, self.jitter_s)
        return x if x > 0 else 0.0

    @property
    def upper_s(self) -> float:
        """A practical upper bound (exact for fixed/uniform/empirical; normal +4 sd)."""
        kind = self.kind
        if kind == "fixed":
            x = self.a
        elif kind == "uniform":
            x = self.b
        elif kind == "normal":
            x = self.a + 4 * self.b
        elif kind == "lognormal":
            x = self.a * math.exp(3.72 * self.b)
        else:
            x = max(self.values)
        return x + self.jitter_s


_KINDS = ("fixed", "uniform", "normal", "lognormal", "empirical")


def fixed(s: float) -> Delay:
    """A constant delay of ``s`` seconds."""
    return Delay("fixed", s)


def empirical(samples_s: Sequence[float], jitter_s: float = 0.0) -> Delay:
    """Resample measured delays (seconds), e.g. interrupt latencies recorded on the real host."""
    return Delay("empirical", values=tuple(float(v) for v in samples_s), jitter_s=jitter_s)


__all__ = ["Delay", "empirical", "fixed"]
