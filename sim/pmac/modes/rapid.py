"""RAPID moves: a jog-type move of every motor to the programmed point (TUM p286; PUM p175;
TSRM p98, p100-101; spec §11.3).

* **Speed**: each motor's Ixx16 (maximum program velocity) when its Ixx90 = 1, else its jog
  speed Ixx22 (counts/ms). The motor needing the longest time at its own speed runs at that
  speed; the others are slowed so all arrive together.
* **Acceleration**: the jog ramp — ``max(Ixx20, 2·Ixx21)`` ms to speed, clamped to Ixx19
  counts/ms² (time extended then) — of that lead motor; a short move never reaches speed
  (a triangle). The other axes follow the same fraction of their distance ``[INF]`` (the
  manual: with unequal accelerations the path is only roughly straight; here it is straight).
* Never blended: a lookahead break (TUM p341) that starts from rest and ends in a stop.
* Axes are mapped to motors by the CS's axis definitions (``#1->1000X``: 1000 counts per
  unit); an axis with no motor uses motor 1 at one count per unit ``[INF]``. Ixx17 plays no
  part; the ``%`` time base stretches the move like any other ``[INF]``; the Ixx92 reaction
  delay before a RAPID starts is not modelled.
"""

from __future__ import annotations

from ..buffers import motion
from ..card.variables import ixx
from ..motor import jog
from .move import RAPID, Move, PlanContext, Profile


class RapidMove(Move):
    """A RAPID move: ``path`` is the lead motor's profile from rest to rest over ``lead``
    counts (program time from 0); every axis is at the same fraction of its distance."""

    __slots__ = ("path", "lead", "t_prog")

    def __init__(
        self, n: int, tm: float, start: dict[str, float], end: dict[str, float],
        path: jog.Profile | None, lead: float, t_prog: float,
    ) -> None:  # fmt: skip
        super().__init__(n, RAPID, tm, 0.0, start, end, None)
        self.path = path
        self.lead = lead
        self.t_prog = t_prog


def _speed_and_rate(ctx: PlanContext, motor: int) -> tuple[float, float]:
    """Motor ``motor``'s RAPID speed (counts/ms) and ramp rate (counts/ms²)."""
    v = ctx.vars.I
    speed = v(ixx(motor, 16)) if v(ixx(motor, 90)) == 1 else v(ixx(motor, 22))
    rate = jog.ramp_rate(speed, v(ixx(motor, 19)), v(ixx(motor, 20)), v(ixx(motor, 21)))
    return abs(speed), rate


def plan(ctx: PlanContext, n: int, start: dict[str, float], end: dict[str, float]) -> Move:
    """The RAPID move of line ``n`` from ``start`` to ``end``."""
    best = (0.0, 0.0, 0.0, 0.0)  # (time at own speed, counts, speed cts/ms, rate cts/ms²)
    for axis in end:
        d = abs(end[axis] - start.get(axis, 0.0))
        if d == 0:
            continue
        for motor, scale in ctx.motors_of(axis) or ((1, 1.0),):
            counts = d * abs(scale)
            speed, rate = _speed_and_rate(ctx, motor)
            t = counts / speed if speed > 0 else motion.MAX_MOVE_S * 1000.0
            if t > best[0]:
                best = (t, counts, speed, rate)
    _, counts, speed, rate = best
    if counts == 0:
        return RapidMove(n, motion.MIN_MOVE_S * ctx.time_scale, start, end, None, 0.0,
                         motion.MIN_MOVE_S)  # fmt: skip
    path = jog.to_position(0.0, 0.0, 0.0, counts, speed * 1000.0, rate)
    t_prog = max(path.t_end or 0.0, motion.MIN_MOVE_S)
    return RapidMove(n, t_prog * ctx.time_scale, start, end, path, counts, t_prog)


class RapidProfile(Profile):
    """Every axis at the lead motor's fraction of the path."""

    kind = RAPID
    breaks = True

    def _fraction(self, m: RapidMove, t: float) -> tuple[float, float]:
        span = m.b_end - m.b_start
        if m.path is None or span <= 0:
            return (1.0 if t >= m.b_end else 0.0), 0.0
        k = m.t_prog / span  # program seconds per real second
        u = min(max((t - m.b_start) * k, 0.0), m.t_prog)
        return m.path.position(u) / m.lead, m.path.velocity(u) / m.lead * k

    def positions(self, m: Move, t: float) -> dict[str, float]:
        assert isinstance(m, RapidMove)
        f, _ = self._fraction(m, t)
        st = m.start
        return {a: st.get(a, 0.0) + (p1 - st.get(a, 0.0)) * f for a, p1 in m.end.items()}

    def velocities(self, m: Move, t: float) -> dict[str, float]:
        assert isinstance(m, RapidMove)
        _, df = self._fraction(m, t)
        st = m.start
        return {a: (p1 - st.get(a, 0.0)) * df for a, p1 in m.end.items()}


PROFILE = RapidProfile()

__all__ = ["PROFILE", "RapidMove", "RapidProfile", "plan"]
