"""The cubic Hermite basis shared by PVT and SPLINE moves.

Both modes run each axis on a cubic between two points with given tangents (PVT: the
programmed velocities, TSRM p463; SPLINE: each piece of the cubic B-spline written in
Hermite form, TUM p290): ``p(s) = h00 p0 + h10 m0 + h01 p1 + h11 m1`` for ``s`` from 0 to 1,
and its rate of change ``dp/ds`` with the derivatives of the same four weights.
"""

from __future__ import annotations


def weights(s: float) -> tuple[float, float, float, float]:
    """``h00, h10, h01, h11`` at ``s``: start point, start tangent, end point, end tangent."""
    s2, s3 = s * s, s * s * s
    return 2 * s3 - 3 * s2 + 1, s3 - 2 * s2 + s, 3 * s2 - 2 * s3, s3 - s2


def rate_weights(s: float) -> tuple[float, float, float, float]:
    """The weights' derivatives in ``s`` (divide by the segment's duration for a velocity)."""
    s2 = s * s
    return 6 * s2 - 6 * s, 3 * s2 - 4 * s + 1, 6 * s - 6 * s2, 3 * s2 - 2 * s


__all__ = ["rate_weights", "weights"]
