"""One motion command on its way through the buffers, and its geometry once it executes.

A :class:`Move` is created when a process (or the command line, or the REST API) issues a
motion command. It names its axes (the BASE group, or the ``AXIS(n)`` axis, in order), its
MTYPE code and its arguments. Its path is fixed when it is loaded into MTYPE and starts
(``begin``): MOVEABS targets and MOVECIRC centres are relative to where the axes are then.

Arguments map in BASE order: the first to the base axis, the next to the next axis of the
group (spec §9.8). Interpolated moves use the base axis' SPEED / ACCEL / DECEL along the
vector path (``[BK]``). MOVECIRC end and centre are relative to the start point; direction 0
turns positively (anticlockwise from the base axis towards the next axis), 1 negatively
(spec §9.7); an end point equal to the start is a full circle. DATUM(n) with n > 0 is modelled
as a return to position 0 at CREEP speed (no datum switch is simulated, ``[INF]``).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from motionsim.sim.trio.mtypes import MTYPE
from motionsim.sim.trio.profile import Profile, endless, plan, trapezoid

if TYPE_CHECKING:
    from motionsim.sim.trio.axis import Axis


class Move:
    """A move command: placed in a process buffer, NTYPE or MTYPE, then executed."""

    __slots__ = (
        "id", "kind", "mtype", "axes", "args", "process", "text",
        "start_tick", "end_tick", "t_start", "profile", "p0", "unit", "circ", "end_pos",
        "v0", "length", "params", "merged_into", "cancelled",
    )

    def __init__(
        self,
        id: int,
        kind: str,
        axes: tuple[int, ...],
        args: tuple[float, ...],
        process: int,
        text: str = "",
    ) -> None:
        self.id = id
        self.kind = kind
        self.mtype = MTYPE[kind]
        self.axes = axes
        self.args = args
        self.process = process
        self.text = text
        self.start_tick: int | None = None
        self.end_tick: int | None = None
        self.t_start = 0.0
        self.profile: Profile | None = None
        self.p0: tuple[float, ...] = ()
        self.unit: tuple[float, ...] = ()
        self.circ: tuple[float, ...] = ()
        self.end_pos: tuple[float, ...] = ()
        self.v0 = 0.0  # path speed at the start (> 0 when merged onto the previous move)
        self.length = 0.0
        self.params: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)
        self.merged_into: Move | None = None  # MERGE: the next move runs on at speed
        self.cancelled = False

    def __repr__(self) -> str:
        return f"<Move #{self.id} {self.kind}{self.args} axes={self.axes} p={self.process}>"

    # -- geometry --------------------------------------------------------------------------

    def begin(self, tick: int, t_start: float, axes: list[Axis], v0: float = 0.0) -> None:
        """Fix the path from the axes' present positions; the move starts at ``tick``.

        ``t_start`` is the origin of the profile (``tau`` = 0): the servo instant of ``tick``,
        or for a merged move the exact instant the previous move's profile ended, where it
        left off at path speed ``v0``.
        """
        base = axes[0]
        self.p0 = p0 = tuple([ax.position() for ax in axes])
        self.start_tick, self.t_start = tick, t_start
        speed = base.speed
        sramp_s = base.sramp / 1000.0
        self.v0 = v0
        kind, a = self.kind, self.args
        if kind == "MOVE" or kind == "MOVEABS" or kind == "DATUM":
            if len(p0) == 1:
                x0 = p0[0]
                d = a[0] if kind == "MOVE" else (a[0] - x0 if kind == "MOVEABS" else -x0)
                length = d if d >= 0.0 else -d
                self.unit = (1.0,) if d >= 0.0 else (-1.0,)
                self.end_pos = (x0 + d,)
            else:
                rel = kind == "MOVE"
                deltas = a if rel else tuple([x - p for x, p in zip(a, p0, strict=True)])
                length = math.sqrt(sum([d * d for d in deltas]))
                self.unit = tuple([d / length for d in deltas]) if length > 0.0 else deltas
                self.end_pos = tuple([p + d for p, d in zip(p0, deltas, strict=True)])
            if kind == "DATUM":
                speed = base.creep
            self._plan(length, speed, base.accel, base.decel, sramp_s)
        elif kind == "FORWARD" or kind == "REVERSE":
            self.unit = (1.0,) if kind == "FORWARD" else (-1.0,)
            self.profile = endless(speed, base.accel, sramp_s)
            self.end_pos = p0
        else:  # MOVECIRC, MHELICAL
            e1, e2, c1, c2, direction = a[:5]
            cx, cy = p0[0] + c1, p0[1] + c2
            r = math.hypot(c1, c2)
            th0 = math.atan2(-c2, -c1)
            th1 = math.atan2(p0[1] + e2 - cy, p0[0] + e1 - cx)
            sign = 1.0 if int(direction) == 0 else -1.0
            sweep = (sign * (th1 - th0)) % (2.0 * math.pi)
            if sweep < 1e-9:
                sweep = 2.0 * math.pi
            d3 = a[5] if kind == "MHELICAL" else 0.0
            length = math.hypot(r * sweep, d3)
            end = [p0[0] + e1, p0[1] + e2]
            if kind == "MHELICAL":
                end.append(p0[2] + d3)
            self.end_pos = tuple(end)
            self.circ = (cx, cy, r, th0, sign * sweep, d3, length)
            self._plan(length, speed, base.accel, base.decel, sramp_s)

    def _plan(self, length: float, speed: float, accel: float, decel: float, ts: float) -> None:
        self.length = length
        self.params = (speed, accel, decel, ts)
        if ts == 0.0 and self.v0 == 0.0:  # the common case: a plain trapezoid
            self.profile = trapezoid(length, speed, accel, decel)
        else:
            self.profile = plan(length, speed, accel, decel, sramp_s=ts, v0=self.v0)

    def merged_profile(self) -> Profile:
        """The same move planned to end at speed (MERGE with the next move loaded)."""
        speed, accel, decel, ts = self.params
        return plan(self.length, speed, accel, decel, sramp_s=ts, v0=self.v0, stop=False)

    def _at(self, s: float) -> tuple[float, ...]:
        """Axis positions a path distance ``s`` along the move."""
        if self.circ:
            cx, cy, r, th0, sweep, d3, length = self.circ
            f = s / length if length > 0.0 else 1.0
            th = th0 + sweep * f
            xy = (cx + r * math.cos(th), cy + r * math.sin(th))
            return xy + (self.p0[2] + d3 * f,) if len(self.p0) == 3 else xy
        return tuple([p + u * s for p, u in zip(self.p0, self.unit, strict=True)])

    def positions(self, tau: float) -> tuple[float, ...]:
        """Demand positions of the move's axes ``tau`` seconds after its start."""
        prof = self.profile
        assert prof is not None
        if tau >= prof.duration:
            return self.end_pos
        return self._at(prof.s(tau))

    def final_positions(self) -> tuple[float, ...]:
        """Where the axes are when the move has ended (exact targets for a full move)."""
        return self.end_pos

    def cut(self, profile: Profile) -> None:
        """CANCEL: the move now follows ``profile`` and ends where that profile stops."""
        self.profile = profile
        self.cancelled = True
        self.merged_into = None
        self.end_pos = self._at(profile.length)

    def speed(self, tau: float) -> float:
        return self.profile.v(tau) if self.profile is not None else 0.0


__all__ = ["Move"]
