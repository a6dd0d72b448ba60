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

from sim.trio.mtypes import MTYPE
from sim.trio.profile import Profile, endless, trapezoid

if TYPE_CHECKING:
    from sim.trio.axis import Axis


class Move:
    """A move command: placed in a process buffer, NTYPE or MTYPE, then executed."""

    __slots__ = (
        "id", "kind", "mtype", "axes", "args", "process", "text",
        "start_tick", "end_tick", "t_start", "profile", "p0", "_pos", "end_pos", "units",
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
        self.end_pos: tuple[float, ...] = ()
        self.units: tuple[float, ...] = ()
        self._pos = None

    def __repr__(self) -> str:
        return f"<Move #{self.id} {self.kind}{self.args} axes={self.axes} p={self.process}>"

    # -- geometry --------------------------------------------------------------------------

    def begin(self, tick: int, t_start: float, axes: list[Axis]) -> None:
        """Fix the path from the axes' present positions; the move starts at ``tick``."""
        self.start_tick, self.t_start = tick, t_start
        base = axes[0]
        self.p0 = p0 = tuple(ax.position() for ax in axes)
        self.units = tuple(ax.units for ax in axes)
        speed, accel, decel = base.speed, base.accel, base.decel
        kind, a = self.kind, self.args
        if kind in ("MOVE", "MOVEABS", "DATUM"):
            if kind == "MOVE":
                deltas = a
            elif kind == "MOVEABS":
                deltas = tuple(x - p for x, p in zip(a, p0, strict=True))
            else:
                deltas = (-p0[0],)
                speed = base.creep
            length = math.sqrt(sum(d * d for d in deltas))
            self.end_pos = tuple(p + d for p, d in zip(p0, deltas, strict=True))
            self.profile = trapezoid(length, speed, accel, decel)
            if length > 0.0:
                unit = tuple(d / length for d in deltas)
                self._pos = lambda s: tuple(
                    p + u * s for p, u in zip(p0, unit, strict=True)
                )
            else:
                self._pos = lambda s: p0
        elif kind in ("FORWARD", "REVERSE"):
            sign = 1.0 if kind == "FORWARD" else -1.0
            self.profile = endless(speed, accel)
            self.end_pos = p0
            self._pos = lambda s: (p0[0] + sign * s,)
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
            arc = r * sweep
            d3 = a[5] if kind == "MHELICAL" else 0.0
            length = math.hypot(arc, d3)
            end = [p0[0] + e1, p0[1] + e2]
            if kind == "MHELICAL":
                end.append(p0[2] + d3)
            self.end_pos = tuple(end)
            self.profile = trapezoid(length, speed, accel, decel)

            def pos(s: float) -> tuple[float, ...]:
                f = s / length if length > 0.0 else 1.0
                th = th0 + sign * sweep * f
                xy = (cx + r * math.cos(th), cy + r * math.sin(th))
                return xy + (p0[2] + d3 * f,) if kind == "MHELICAL" else xy

            self._pos = pos

    def positions(self, tau: float) -> tuple[float, ...]:
        """Demand positions of the move's axes ``tau`` seconds after its start."""
        prof = self.profile
        assert prof is not None and self._pos is not None
        if tau >= prof.duration:
            return self.final_positions()
        return self._pos(prof.s(tau))

    def final_positions(self) -> tuple[float, ...]:
        """Where the axes are when the move has ended (exact targets for a full move)."""
        return self.end_pos

    def cut(self, profile: Profile) -> None:
        """CANCEL: the move now follows ``profile`` and ends where that profile stops."""
        assert self._pos is not None
        self.profile = profile
        self.end_pos = self._pos(profile.length)

    def speed(self, tau: float) -> float:
        return self.profile.v(tau) if self.profile is not None else 0.0


__all__ = ["Move"]
