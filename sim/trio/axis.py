"""One Trio axis: its profile parameters, its two move buffers, and where it is.

``mtype`` holds the move executing now (MTYPE), ``ntype`` the next move waiting for it
(NTYPE); :mod:`motionsim.sim.trio.buffers` alone moves moves between them. Positions are in user
units (encoder edges / UNITS). DPOS, ENDMOVE, REMAIN and VP_SPEED are computed from the executing
move's profile at the last servo cycle at or before the instant asked — the axis never wakes
once per servo period. MPOS equals DPOS (no following error is modelled).

Parameter defaults (SPEED 1000, ACCEL 1000, DECEL 1000, CREEP 10, UNITS 1) are ``[BK]``; set
them per axis with ``set_axis`` or ``PATCH /axes/{n}``. A new SPEED / ACCEL / DECEL applies to
moves that start after it is written (the move executing keeps its profile — a simplification
of the controller, whose profile generator follows SPEED on the fly).

MERGE (switch, default OFF) and SRAMP (ms, default 0) shape the profile: see
:mod:`motionsim.sim.trio.buffers` for when moves merge and :mod:`motionsim.sim.trio.profile` for
the S-ramp; both are ``[BK]`` (the TRM pages were not reachable). Like SPEED, they apply to moves
that start (or, for MERGE, reach NTYPE) after they are written.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from motionsim.sim.errors import InvalidValue
from motionsim.sim.timing import ServoClock
from motionsim.sim.trio.mtypes import IDLE

if TYPE_CHECKING:
    import simpy
    from motionsim.sim.trio.moves import Move

DEFAULTS: dict[str, float] = {
    "speed": 1000.0,
    "accel": 1000.0,
    "decel": 1000.0,
    "creep": 10.0,
    "units": 1.0,
    "merge": 0.0,
    "sramp": 0.0,
}

#: Parameters that may be 0: MERGE is a switch (any non-zero value is ON, ``TRUE`` = -1),
#: SRAMP a time in ms, 0..250 (``[BK]``, see :mod:`motionsim.sim.trio.profile`).
_SWITCHES = {"merge"}
SRAMP_MAX_MS = 250.0


class Axis:
    """Axis ``n``: parameters, MTYPE / NTYPE buffers, position."""

    __slots__ = (
        "n", "env", "clock", "speed", "accel", "decel", "creep", "units", "mtype", "ntype", "pos",
        "merge", "sramp",
    )

    def __init__(
        self, n: int, env: simpy.Environment, clock: ServoClock, params: dict | None = None
    ) -> None:
        self.n = n
        self.env = env
        self.clock = clock
        self.mtype: Move | None = None
        self.ntype: Move | None = None
        self.pos = 0.0  # committed demand position (user units) while no move executes
        self.speed = self.accel = self.decel = self.creep = self.units = 0.0
        self.merge = self.sramp = 0.0
        self.set(**{**DEFAULTS, **(params or {})})

    # -- parameters ------------------------------------------------------------------------

    def set(self, **params: float) -> None:
        """Write profile parameters; all are checked before any is written."""
        for key, value in params.items():
            if key not in DEFAULTS:
                raise InvalidValue(f"axis {self.n} has no parameter {key!r}", field=key)
            if key in _SWITCHES:
                if not isinstance(value, (int, float)) or value != value:
                    raise InvalidValue(
                        f"{key.upper()} AXIS({self.n}) must be ON or OFF, got {value!r}",
                        field=key,
                    )
                continue
            if key == "sramp":
                if not isinstance(value, (int, float)) or not 0 <= value <= SRAMP_MAX_MS:
                    raise InvalidValue(
                        f"SRAMP AXIS({self.n}) must be 0..{SRAMP_MAX_MS:g} ms, got {value!r}",
                        field=key,
                    )
                continue
            if not isinstance(value, (int, float)) or not value > 0 or value != value:
                raise InvalidValue(
                    f"{key.upper()} AXIS({self.n}) must be a positive number, got {value!r}",
                    field=key,
                )
        for key, value in params.items():
            if key == "units" and self.units:
                # The encoder count stays; the user-unit position rescales (DPOS = edges/UNITS).
                self.pos = self.pos * self.units / float(value)
            if key in _SWITCHES:
                value = 1.0 if value else 0.0
            setattr(self, key, float(value))

    # -- buffers ---------------------------------------------------------------------------

    @property
    def mtype_code(self) -> int:
        m = self.mtype
        return m.mtype if m is not None else IDLE

    @property
    def ntype_code(self) -> int:
        m = self.ntype
        return m.mtype if m is not None else IDLE

    # -- position from the profile ---------------------------------------------------------

    def _tau(self, m: Move, t: float) -> float | None:
        if m.start_tick is None or m.profile is None:
            return None
        k = self.clock.index(t)
        if k < m.start_tick:
            return None
        return self.clock.t(k) - m.t_start

    def position(self, t: float | None = None) -> float:
        """DPOS at ``t`` (default now), as of the last servo cycle."""
        m = self.mtype
        if m is None:
            return self.pos
        tau = self._tau(m, self.env.now if t is None else t)
        if tau is None:
            return self.pos
        return m.positions(tau)[m.axes.index(self.n)]

    def endmove(self) -> float:
        """ENDMOVE: the end position of the executing move (DPOS when idle or endless)."""
        m = self.mtype
        if m is None or m.start_tick is None or m.kind in ("FORWARD", "REVERSE"):
            return self.position()
        return m.final_positions()[m.axes.index(self.n)]

    def remain(self) -> float:
        """REMAIN: path distance still to go in the executing move (0 when idle or endless)."""
        m = self.mtype
        if m is None or m.profile is None or m.kind in ("FORWARD", "REVERSE"):
            return 0.0
        tau = self._tau(m, self.env.now)
        if tau is None:
            return m.profile.length
        return max(0.0, m.profile.length - m.profile.s(tau))

    def vp_speed(self) -> float:
        """VP_SPEED: the profile generator's path speed now."""
        m = self.mtype
        if m is None:
            return 0.0
        tau = self._tau(m, self.env.now)
        return 0.0 if tau is None else m.speed(tau)

    def moves_buffered(self) -> int:
        """MOVES_BUFFERED: MTYPE and NTYPE slots in use (whether the controller counts the
        executing move is not documented, spec §1.4 ``[INF]``; here it does)."""
        return (self.mtype is not None) + (self.ntype is not None)

    def read(self, name: str) -> float:
        """An axis parameter by its BASIC name (``MTYPE``, ``DPOS``, ``SPEED`` ...)."""
        if name == "MTYPE":
            return float(self.mtype_code)
        if name == "NTYPE":
            return float(self.ntype_code)
        if name in ("DPOS", "MPOS"):
            return self.position()
        if name == "ENDMOVE":
            return self.endmove()
        if name == "REMAIN":
            return self.remain()
        if name == "IDLE":
            return -1.0 if self.mtype is None and self.ntype is None else 0.0
        if name == "VP_SPEED":
            return self.vp_speed()
        if name == "MOVES_BUFFERED":
            return float(self.moves_buffered())
        return float(getattr(self, name.lower()))

    def snapshot(self) -> dict[str, float | int]:
        """The API.md axis resource."""
        dpos = self.position()
        return {
            "axis": self.n,
            "mtype": self.mtype_code,
            "ntype": self.ntype_code,
            "dpos": dpos,
            "mpos": dpos,
            "endmove": self.endmove(),
            "remain": self.remain(),
            "speed": self.speed,
            "accel": self.accel,
            "decel": self.decel,
            "units": self.units,
            "creep": self.creep,
            "merge": self.merge,
            "sramp": self.sramp,
            "vp_speed": self.vp_speed(),
            "moves_buffered": self.moves_buffered(),
        }


__all__ = ["DEFAULTS", "Axis"]
