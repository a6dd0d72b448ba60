"""One Trio axis: its profile parameters, its two move buffers, and where it is.

``mtype`` holds the move executing now (MTYPE), ``ntype`` the next move waiting for it
(NTYPE); :mod:`motionsim.sim.trio.motion.buffers` alone moves moves between them. Positions are in
user
units (encoder edges / UNITS). DPOS, ENDMOVE, REMAIN and VP_SPEED are computed from the executing
move's profile at the last servo cycle at or before the instant asked — the axis never wakes
once per servo period. MPOS = DPOS - FE, where FE is the following-error model of
:meth:`Axis.following_error` (0 unless the axis has an ``fe_lag``: then MPOS equals DPOS).

Parameter defaults (SPEED 1000, ACCEL 1000, DECEL 1000, CREEP 10, UNITS 1) are ``[BK]``; set
them per axis with ``set_axis`` or ``PATCH /axes/{n}``. SPEED, ACCEL and DECEL written while the
axis is the base axis of the executing move re-plan that move at once (see
:mod:`motionsim.sim.trio.motion.moves`); SPEED may be 0 (the move holds). FORCE_SPEED (default 1000
``[BK]``) is the speed of the SP moves, captured when each is issued.

OFFPOS (write) shifts the axis' coordinates by the value at the next servo period and reads
back 0 once applied; DEFPOS(p) declares the position to be p at the next servo period, and
OFFPOS reads the pending shift until then (TRM, MC216 listing p. 220: DEFPOS and OFFPOS take
effect at the next servo update; DEFPOS becomes an OFFPOS internally, so ``WAIT UNTIL
OFFPOS=0`` waits for it).

MERGE (switch, default OFF) and SRAMP (ms, default 0) shape the profile: see
:mod:`motionsim.sim.trio.motion.buffers` for when moves merge and
:mod:`motionsim.sim.trio.motion.profile` for
the S-ramp; both are ``[BK]`` (the TRM pages were not reachable). Unlike SPEED, they apply to
moves that start (or, for MERGE, reach NTYPE) after they are written (a CANCEL uses the SRAMP
of the moment).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

from ...bounds import TRIO_RATE, TRIO_UNITS
from ...errors import InvalidValue
from ...timing import ServoClock
from ..card import scaling
from ..card.axis_status import StoredParams
from .mtypes import IDLE

if TYPE_CHECKING:
    import simpy

    from .moves import Move

DEFAULTS: dict[str, float] = {
    "speed": 1000.0,
    "accel": 1000.0,
    "decel": 1000.0,
    "creep": 10.0,
    "units": 1.0,
    "merge": 0.0,
    "sramp": 0.0,
    "force_speed": 1000.0,
    "fe_lag": 0.0,
}

#: Parameters that may be 0: MERGE is a switch (any non-zero value is ON, ``TRUE`` = -1),
#: SRAMP a time in ms, 0..250 (``[BK]``, see :mod:`motionsim.sim.trio.motion.profile`),
#: ``fe_lag`` the servo's lag in seconds, 0..1 (the following-error model: a setting of the
#: simulated plant, PATCH /axes/{n} or config, not a Trio parameter).
_SWITCHES = {"merge"}
#: Speeds that may be 0 (SPEED = 0 holds the executing move, spec §10.5).
_ZERO_OK = {"speed", "force_speed"}
#: Parameters whose change re-plans the executing move.
PROFILE_PARAMS = frozenset({"speed", "accel", "decel"})
SRAMP_MAX_MS = 250.0
FE_LAG_MAX_S = 1.0


class Axis:
    """Axis ``n``: parameters, MTYPE / NTYPE buffers, position."""

    __slots__ = (
        "n", "env", "clock", "speed", "accel", "decel", "creep", "units", "mtype", "ntype", "pos",
        "merge", "sramp", "force_speed", "on_profile_change", "queued",
        "stored", "added", "added_edges0", "added_fixed", "encoder_ratio", "step_ratio",
        "pending", "ahead", "fe_lag", "error_bits",
    )

    def __init__(
        self, n: int, env: simpy.Environment, clock: ServoClock, params: dict | None = None
    ) -> None:
        self.n = n
        self.env = env
        self.clock = clock
        self.mtype: Move | None = None
        self.ntype: Move | None = None
        #: MC4xx look-ahead: the moves buffered behind NTYPE (NTYPE is its first entry; the
        #: whole look-ahead holds LIMIT_BUFFERED moves, TJ2H-57)
        self.ahead: list[Move] = []
        self.pos = 0.0  # committed demand position (user units) while no move executes
        self.speed = self.accel = self.decel = self.creep = self.units = 0.0
        self.merge = self.sramp = self.force_speed = self.fe_lag = 0.0
        #: AXISSTATUS bits latched by an error (bit 8: FE_LIMIT exceeded) until DATUM(0)
        self.error_bits = 0
        #: DEFPOS / OFFPOS writes of this servo period, in order: ("DEFPOS", p) / ("OFFPOS", d)
        self.pending: list[tuple[str, float]] = []
        self.stored: StoredParams = StoredParams()  # the controller gives its own
        self.added: Axis | None = None  # ADDAX: the axis whose demand changes are added
        self.added_edges0 = 0.0  # that axis' demand (edges) when the link was made
        self.added_fixed = 0.0  # what earlier ADDAX links added (user units)
        self.encoder_ratio: tuple[float, float] = (1.0, 1.0)  # ENCODER_RATIO(den, num)
        self.step_ratio: tuple[float, float] = (1.0, 1.0)  # STEP_RATIO(den, num)
        self.on_profile_change: Callable[[Axis], None] | None = None
        self.queued = 0  # moves for this axis waiting in a process buffer
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
            if key == "fe_lag":
                if not isinstance(value, (int, float)) or not 0 <= value <= FE_LAG_MAX_S:
                    raise InvalidValue(
                        f"fe_lag of axis {self.n} must be 0..{FE_LAG_MAX_S:g} s, got {value!r}",
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
            if key == "units":
                try:
                    TRIO_UNITS.check(value, key)
                except InvalidValue:
                    raise InvalidValue(f"UNITS AXIS({self.n}) must be {TRIO_UNITS.describe()}, "
                                       f"got {value!r}", field=key) from None
                continue
            low_ok = key in _ZERO_OK and isinstance(value, (int, float)) and value == 0
            if not low_ok and (
                not isinstance(value, (int, float)) or not 0 < value <= TRIO_RATE.high
            ):
                raise InvalidValue(
                    f"{key.upper()} AXIS({self.n}) must be {TRIO_RATE.describe()}, "
                    f"got {value!r}", field=key,
                )
        replan = self.on_profile_change is not None and any(
            getattr(self, k) != float(params[k]) for k in PROFILE_PARAMS.intersection(params)
        )
        for key, value in params.items():
            if key == "units" and self.units:
                # The encoder count stays; the user-unit position rescales (DPOS = edges/UNITS).
                self.pos = self.pos * self.units / float(value)
                self.added_fixed = self.added_fixed * self.units / float(value)
                self.stored.units_changed(self.units, float(value))
            if key in _SWITCHES:
                value = 1.0 if value else 0.0
            setattr(self, key, float(value))
        if replan:
            self.on_profile_change(self)  # type: ignore[misc]

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

    def own_position(self, t: float | None = None) -> float:
        """The demand of the axis' own moves at ``t`` (default now), as of the last servo
        cycle: what its moves start from (ADDAX adds to it, :meth:`position`)."""
        m = self.mtype
        if m is None or m.start_tick is None:  # idle, or the move is only just loading
            return self.pos
        tau = self._tau(m, self.env.now if t is None else t)
        if tau is None:
            return self.pos
        return m.positions(tau)[m.axes.index(self.n)]

    def position(self, t: float | None = None) -> float:
        """DPOS at ``t`` (default now), as of the last servo cycle, unwrapped: the axis' own
        demand plus what ADDAX adds (M216-203: the added axis' demand changes, summed in
        encoder edges)."""
        own = self.own_position(t)
        if self.added is None:
            return own + self.added_fixed if self.added_fixed else own
        return own + self.added_fixed + self._added_now(t)

    def _added_now(self, t: float | None) -> float:
        link = self.added
        assert link is not None
        return (link.position(t) * link.units - self.added_edges0) / self.units

    def add_axis(self, link: Axis | None) -> None:
        """ADDAX(link) / ADDAX(-1): from now on the demand changes of ``link`` add to this
        axis' (none); what was added so far stays (the axis does not jump). ValueError for
        a link back to this axis."""
        if self.added is not None:
            self.added_fixed += self._added_now(None)
        self.added = None
        if link is None:
            return
        a: Axis | None = link
        while a is not None:
            if a is self:
                raise ValueError(f"ADDAX({link.n}) AXIS({self.n}) would add the axis to itself")
            a = a.added
        self.added = link
        self.added_edges0 = link.position() * link.units

    def wrap(self, x: float) -> float:
        """``x`` as DPOS / MPOS read it: within the REP_DIST range (REP_OPTION bit 0)."""
        st = self.stored.values
        return scaling.wrap(x, self.units, st["REP_DIST"], int(st["REP_OPTION"]))

    def dpos(self) -> float:
        """DPOS as read: whole edges, wrapped at REP_DIST."""
        return self.wrap(self.position())

    def following_error(self, t: float | None = None) -> float:
        """FE = DPOS - MPOS at ``t`` (default now), as of the last servo cycle.

        The model (``[INF]``, docs/trio.md "Following error"): the servo loop makes the
        measured position follow the demand ``fe_lag`` seconds behind, so FE is ``fe_lag``
        times the demand speed of the last servo period (DPOS now less DPOS one period
        earlier, over the period). 0 with ``fe_lag`` 0 — the power-up setting, MPOS = DPOS —
        and whenever the demand is at rest."""
        if self.fe_lag == 0.0:
            return 0.0
        now = self.env.now if t is None else t
        k = self.clock.index(now)
        if k <= 0:
            return 0.0
        here, before = self.position(self.clock.t(k)), self.position(self.clock.t(k - 1))
        return self.fe_lag * (here - before) / self.clock.period_s

    def mpos(self) -> float:
        """MPOS as read: DPOS less the following error, wrapped at REP_DIST."""
        fe = self.following_error()
        return self.wrap(self.position() - fe) if fe else self.dpos()

    def endmove(self) -> float:
        """ENDMOVE: the end position of the executing move (DPOS when idle or endless)."""
        m = self.mtype
        end = None if m is None or m.start_tick is None else m.endmove(m.axes.index(self.n))
        return self.position() if end is None else end

    def remain(self) -> float:
        """REMAIN: path distance still to go in the executing move (0 when idle or endless)."""
        m = self.mtype
        if m is None or m.profile is None:
            return 0.0
        return m.remaining(self._tau(m, self.env.now))

    # -- DEFPOS / OFFPOS ---------------------------------------------------------------------

    @property
    def offset(self) -> float:
        """OFFPOS written: a shift applied at the next servo period (reads the pending one)."""
        return self.offpos()

    @offset.setter
    def offset(self, value: float) -> None:
        self.pending.append(("OFFPOS", float(value)))

    @property
    def defpos(self) -> float | None:
        """DEFPOS(p) pending for the next servo period (the last one written), else None."""
        for kind, v in reversed(self.pending):
            if kind == "DEFPOS":
                return v
        return None

    @defpos.setter
    def defpos(self, value: float | None) -> None:
        if value is not None:
            self.pending.append(("DEFPOS", float(value)))

    def pending_shift(self, t: float | None = None) -> float:
        """The shift the DEFPOS / OFFPOS writes of this servo period make, applied in the
        order written: DEFPOS(p) makes the position p, OFFPOS(d) then moves it by d (two
        OFFPOS writes add up). None of them is lost (TRM p. 8-30: both act at the next servo
        update, DEFPOS as an OFFPOS)."""
        shift = 0.0
        for kind, v in self.pending:
            shift = (v - self.position(t)) if kind == "DEFPOS" else shift + v
        return shift

    def offpos(self) -> float:
        """OFFPOS: the shift still to be applied at the next servo period (0 once applied)."""
        return self.pending_shift() if self.pending else 0.0

    def vp_speed(self) -> float:
        """VP_SPEED: the profile generator's path speed now."""
        m = self.mtype
        if m is None:
            return 0.0
        tau = self._tau(m, self.env.now)
        return 0.0 if tau is None else m.speed(tau)

    def moves_buffered(self) -> int:
        """MOVES_BUFFERED: MTYPE, NTYPE and look-ahead slots in use (whether the controller
        counts the executing move is not documented, spec §1.4 ``[INF]``; here it does)."""
        return (self.mtype is not None) + (self.ntype is not None) + len(self.ahead)

    def buffered(self) -> int:
        """Moves in the look-ahead (NTYPE included)."""
        return (self.ntype is not None) + len(self.ahead)

    def buffer(self, m: Move) -> None:
        """``m`` joins the look-ahead: NTYPE if that is free, else behind the others."""
        if self.ntype is None:
            self.ntype = m
        else:
            self.ahead.append(m)

    def unbuffer(self, m: Move) -> None:
        """``m`` leaves the look-ahead (loaded or cancelled); the next one becomes NTYPE."""
        if self.ntype is m:
            self.ntype = self.ahead.pop(0) if self.ahead else None
        elif m in self.ahead:
            self.ahead.remove(m)

    def last_buffered(self) -> Move | None:
        """The move in the last position of the axis' buffers (MTYPE when none waits)."""
        if self.ahead:
            return self.ahead[-1]
        return self.ntype if self.ntype is not None else self.mtype

    def read(self, name: str) -> float:
        """An axis parameter by its BASIC name (``MTYPE``, ``DPOS``, ``SPEED`` ...)."""
        if name == "MTYPE":
            return float(self.mtype_code)
        if name == "NTYPE":
            return float(self.ntype_code)
        if name == "DPOS":
            return self.dpos()
        if name == "MPOS":
            return self.mpos()
        if name == "ENDMOVE":
            return self.wrap(self.endmove())
        if name == "REMAIN":
            return self.remain()
        if name == "IDLE":  # no move executing, next, or on its way in a process buffer
            idle = self.mtype is None and self.ntype is None and not self.queued
            return -1.0 if idle else 0.0
        if name == "VP_SPEED":
            return self.vp_speed()
        if name == "MOVES_BUFFERED":
            return float(self.moves_buffered())
        if name == "OFFPOS":
            return self.offpos()
        return float(getattr(self, name.lower()))

    def snapshot(self) -> dict[str, float | int]:
        """The API.md axis resource."""
        dpos = self.dpos()
        return {
            "axis": self.n,
            "mtype": self.mtype_code,
            "ntype": self.ntype_code,
            "dpos": dpos,
            "mpos": self.mpos(),
            "endmove": self.wrap(self.endmove()),
            "remain": self.remain(),
            "speed": self.speed,
            "accel": self.accel,
            "decel": self.decel,
            "units": self.units,
            "creep": self.creep,
            "merge": self.merge,
            "sramp": self.sramp,
            "force_speed": self.force_speed,
            "fe": self.following_error(),
            "fe_lag": self.fe_lag,
            "vp_speed": self.vp_speed(),
            "moves_buffered": self.moves_buffered(),
        }


__all__ = ["DEFAULTS", "Axis"]
