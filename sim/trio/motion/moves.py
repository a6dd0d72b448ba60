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

SPEED, ACCEL and DECEL written while a move runs act on it (spec §10.5: the TRM's "the speed
may be changed at any time", M206-207; a production pause program writes SPEED=0 to hold moves
and restores SPEED to resume them): the move is re-planned from where it is at the servo period
of the write — ramping at ACCEL / DECEL to the new SPEED, SPEED = 0 holding it where it stopped
with MTYPE still loaded — along the same path to the same end (``replan``). The SP moves
(MOVESP, MOVEABSSP, MOVECIRCSP, MHELICALSP) run at the FORCE_SPEED captured when they were
issued, so that each buffered move keeps its own speed, and ignore SPEED (spec §10.2 ``[BK]``:
the TRM pages were not reachable); ENDMOVE_SPEED is not simulated (they end at rest).
MOVEMODIFY (MTYPE 5, spec §10.2) is a MOVEABS when it is loaded as a move of its own.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from ..card.scaling import whole_edges
from .mtypes import MTYPE, SP_GEOMETRY
from .profile import Profile, endless, hold, plan, trapezoid

if TYPE_CHECKING:
    from .axis import Axis


class Move:
    """A move command: placed in a process buffer, NTYPE or MTYPE, then executed."""

    __slots__ = (
        "id", "kind", "mtype", "axes", "args", "process", "text",
        "start_tick", "end_tick", "t_start", "profile", "p0", "unit", "circ", "end_pos",
        "v0", "length", "params", "merged_into", "cancelled", "geom", "s_off", "force_speed",
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
        #: The geometry: an SP move is its plain move, MOVEMODIFY loaded alone a MOVEABS.
        self.geom = "MOVEABS" if kind == "MOVEMODIFY" else SP_GEOMETRY.get(kind, kind)
        self.s_off = 0.0  # path run before the profile's origin (re-planned moves)
        self.force_speed: float | None = None  # SP moves: FORCE_SPEED when issued

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
        if len(axes) == 1:
            self.p0 = p0 = (base.own_position(),)
        else:
            self.p0 = p0 = tuple([ax.own_position() for ax in axes])
        self.start_tick, self.t_start = tick, t_start
        speed = base.speed if self.force_speed is None else self.force_speed
        sramp_s = base.sramp / 1000.0
        self.v0 = v0
        kind, a = self.geom, self.args
        if kind == "MOVE" or kind == "MOVEABS" or kind == "DATUM":
            # every distance in whole encoder edges (TJ1P-27: a fraction above 0.9 rounds up);
            # MOVEABS goes to its target from where DPOS reads (REP_DIST range)
            if len(p0) == 1:
                x0 = p0[0]
                d = a[0] if kind == "MOVE" else (
                    a[0] - base.wrap(base.position()) if kind == "MOVEABS" else -x0)
                u = base.units
                if (d * u) % 1.0 != 0.0:
                    d = whole_edges(d, u)
                length = d if d >= 0.0 else -d
                self.unit = (1.0,) if d >= 0.0 else (-1.0,)
                self.end_pos = (x0 + d,)
            else:
                if kind == "MOVE":
                    deltas = a
                else:
                    deltas = tuple([x - ax.wrap(ax.position())
                                    for x, ax in zip(a, axes, strict=True)])
                deltas = tuple([whole_edges(d, ax.units)
                                for d, ax in zip(deltas, axes, strict=True)])
                length = math.sqrt(sum([d * d for d in deltas]))
                self.unit = tuple([d / length for d in deltas]) if length > 0.0 else deltas
                self.end_pos = tuple([p + d for p, d in zip(p0, deltas, strict=True)])
            if kind == "DATUM":
                speed = base.creep
            self.length = length  # (_plan, one call less on the usual path)
            self._profile(length, speed, base.accel, base.decel, sramp_s)
        elif kind == "FORWARD" or kind == "REVERSE":
            self.unit = (1.0,) if kind == "FORWARD" else (-1.0,)
            self.profile = endless(speed, base.accel, sramp_s)
            self.end_pos = p0
        else:  # MOVECIRC, MHELICAL
            e1, e2, c1, c2, direction = a[:5]
            e1, e2 = whole_edges(e1, axes[0].units), whole_edges(e2, axes[1].units)
            cx, cy = p0[0] + c1, p0[1] + c2
            r = math.hypot(c1, c2)
            th0 = math.atan2(-c2, -c1)
            th1 = math.atan2(p0[1] + e2 - cy, p0[0] + e1 - cx)
            sign = 1.0 if int(direction) == 0 else -1.0
            sweep = (sign * (th1 - th0)) % (2.0 * math.pi)
            if sweep < 1e-9:
                sweep = 2.0 * math.pi
            d3 = whole_edges(a[5], axes[2].units) if kind == "MHELICAL" else 0.0
            length = math.hypot(r * sweep, d3)
            end = [p0[0] + e1, p0[1] + e2]
            if kind == "MHELICAL":
                end.append(p0[2] + d3)
            self.end_pos = tuple(end)
            self.circ = (cx, cy, r, th0, sign * sweep, d3, length)
            self._plan(length, speed, base.accel, base.decel, sramp_s)

    def _plan(self, length: float, speed: float, accel: float, decel: float, ts: float) -> None:
        self.length = length
        self._profile(length, speed, accel, decel, ts)

    def _profile(self, length: float, speed: float, accel: float, decel: float,
                 ts: float) -> None:
        """Plan ``length`` still to go from path speed ``v0`` (SPEED = 0: ramp down, hold)."""
        self.params = (speed, accel, decel, ts)
        if speed <= 0.0:
            self.profile = hold(self.v0, decel, length)
        elif ts == 0.0 and self.v0 == 0.0:  # the common case: a plain trapezoid
            self.profile = trapezoid(length, speed, accel, decel)
        else:
            self.profile = plan(length, speed, accel, decel, sramp_s=ts, v0=self.v0)

    def merged_profile(self) -> Profile:
        """The same move planned to end at speed (MERGE with the next move loaded)."""
        speed, accel, decel, ts = self.params
        rest = self.length - self.s_off
        return plan(rest, speed, accel, decel, sramp_s=ts, v0=self.v0, stop=False)

    def _at(self, s: float) -> tuple[float, ...]:
        """Axis positions a path distance ``s`` along the move."""
        if self.circ:
            cx, cy, r, th0, sweep, d3, length = self.circ
            f = s / length if length > 0.0 else 1.0
            th = th0 + sweep * f
            xy = (cx + r * math.cos(th), cy + r * math.sin(th))
            return xy + (self.p0[2] + d3 * f,) if len(self.p0) == 3 else xy
        return tuple([p + u * s for p, u in zip(self.p0, self.unit, strict=True)])

    def at(self, s: float) -> tuple[float, ...]:
        """Axis positions a path distance ``s`` (from the start of the path) along the move."""
        return self._at(s)

    def positions(self, tau: float) -> tuple[float, ...]:
        """Demand positions of the move's axes ``tau`` seconds after its start."""
        prof = self.profile
        assert prof is not None
        if tau >= prof.duration:
            return self.end_pos
        return self._at(self.s_off + prof.s(tau))

    def final_positions(self) -> tuple[float, ...]:
        """Where the axes are when the move has ended (exact targets for a full move)."""
        return self.end_pos

    def cut(self, profile: Profile) -> None:
        """CANCEL: the move now follows ``profile`` and ends where that profile stops."""
        self.profile = profile
        self.cancelled = True
        self.merged_into = None
        self.end_pos = self._at(self.s_off + profile.length)

    def cancel_at(self, tau: float, decel: float, sramp_s: float = 0.0) -> None:
        """CANCEL ``tau`` after the profile origin: ramp down to rest at ``decel`` (S-shaped
        over ``sramp_s`` when the axis has an SRAMP)."""
        assert self.profile is not None
        self.cut(self.profile.cancelled_at(tau, decel, sramp_s))

    @property
    def endless(self) -> bool:
        return self.geom in ("FORWARD", "REVERSE")

    def remaining(self, tau: float | None) -> float:
        """REMAIN: path distance still to go (0 for FORWARD / REVERSE)."""
        prof = self.profile
        if prof is None or self.endless:
            return 0.0
        if tau is None:
            return prof.length
        return max(0.0, prof.length - prof.s(tau))

    def endmove(self, i: int) -> float | None:
        """ENDMOVE of the move's ``i``-th axis (None: the axis' DPOS, for endless moves)."""
        return None if self.endless else self.end_pos[i]

    def follows_speed(self) -> bool:
        """Whether SPEED / ACCEL / DECEL written now re-plan this move."""
        return (
            self.force_speed is None and not self.cancelled and self.merged_into is None
            and self.geom != "DATUM" and self.profile is not None
        )

    def replan(self, tau: float, tick: int, t: float, axes: list[Axis],
               end: float | None = None) -> None:
        """Re-plan from ``tau`` (the servo instant ``t`` of period ``tick``): the path run so
        far is kept; from here on the base axis' present SPEED / ACCEL / DECEL apply, and with
        ``end`` (MOVEMODIFY, single-axis moves) the move ends at that absolute position."""
        prof = self.profile
        assert prof is not None
        s_here, v_here = prof.s(tau), prof.v(tau)
        base = axes[0]
        speed = base.speed if self.force_speed is None else self.force_speed
        ts = base.sramp / 1000.0
        self.s_off += s_here
        self.v0 = v_here
        self.start_tick, self.t_start = tick, t
        if end is not None:
            here = self._at(self.s_off)[0]
            self.length = self.s_off + abs(end - here)
            self.end_pos = (end,)
        if self.endless:
            rate = base.accel if speed >= v_here else base.decel
            self.profile = endless(speed, rate, ts, v0=v_here) if speed > 0.0 else hold(
                v_here, base.decel, float("inf"))
        else:
            self._profile(self.length - self.s_off, speed, base.accel, base.decel, ts)

    def shift(self, i: int, offset: float) -> None:
        """DEFPOS / OFFPOS: the ``i``-th axis' coordinates move by ``offset`` (the path with
        them, so the axis does not move)."""
        p0, end = list(self.p0), list(self.end_pos)
        p0[i] += offset
        if end:
            end[i] += offset
        self.p0, self.end_pos = tuple(p0), tuple(end)
        if self.circ and i < 2:
            c = list(self.circ)
            c[i] += offset
            self.circ = tuple(c)

    def speed(self, tau: float) -> float:
        return self.profile.v(tau) if self.profile is not None else 0.0

    def needs_tick(self) -> bool:
        """Whether the move must be looked at every servo period while it executes (it ends
        on an outside event: a link distance, an input), see :meth:`tick`."""
        return False

    def tick(self, t: float) -> str | None:
        """One servo period at instant ``t``: None to go on, ``"end"`` when the move is over,
        ``"idle"`` when it needs no more looks."""
        return "idle"


__all__ = ["Move"]
