"""A calculated move and the interface every move mode's profile offers the planner.

A coordinate system's planner turns each move line into a :class:`Move` with the mode's
``plan`` function (one module per mode: :mod:`.linear`, :mod:`.rapid`, :mod:`.dwell`,
:mod:`.pvt`, :mod:`.spline`); the executor then only asks the mode's :class:`Profile` how the
move behaves: whether it blends with its neighbours, whether it breaks lookahead, and where
the axes are at an instant.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, ClassVar, Protocol

from ..buffers.motion import DELAY, DWELL, LINEAR, PVT, RAPID, SPLINE, Arc

if TYPE_CHECKING:
    from ..card.variables import Variables

# Move kinds (index into :data:`motionsim.sim.pmac.modes.PROFILES`): buffers/motion.py.
_BLENDING = frozenset({LINEAR, DELAY, PVT, SPLINE})


class RunTimeError(Exception):
    """A line cannot be calculated (e.g. a PVT time out of range): the coordinate system
    aborts with a run-time error, as when calculation falls behind (TUM p339)."""


class Move:
    """One calculated move (or dwell / delay) and, once started, its profile times.

    ``tm`` is the move time and ``ta`` the blend-ramp time (real seconds, already stretched by
    the time base); ``b_start`` / ``b_end`` are the instants the move passes its programmed
    start and end points (the centres of its ramps); ``prev`` is the move it blended from
    (kept only while this one executes); the per-axis velocities ``v`` are computed on demand
    (only position queries need them); ``ta_stop`` the shortest stop ramp Ixx17 allows.
    """

    __slots__ = (
        "n", "kind", "tm", "ta", "start", "end", "sync", "prev", "_v",
        "b_start", "b_end", "ta_in", "ta_out", "stopping", "ta_stop", "prog",
    )  # fmt: skip

    #: A segmented CIRCLE move's arc (:class:`.linear.ArcMove` has the slot); None here.
    arc: Arc | None = None

    #: Set when the move starts executing (:meth:`.Execution._start_next`).
    b_start: float
    b_end: float

    def __init__(
        self,
        n: int,
        kind: int,
        tm: float,
        ta: float,
        start: dict[str, float],
        end: dict[str, float],
        sync: list[tuple[int, str, float]] | None,
    ) -> None:
        self.n = n
        self.kind = kind
        self.tm = tm
        self.ta = ta
        self.ta_in = ta
        self.start = start
        self.end = end
        self.sync = sync
        self.prev: Move | None = None
        self._v: dict[str, float] | None = None
        self.ta_out = 0.0
        self.stopping = False
        #: The shortest decel to a stop from this move's speed that Ixx17 allows (program
        #: seconds; 0 = no limit), :mod:`.accel_limit`.
        self.ta_stop = 0.0
        #: The fixed program whose line this move is (a CALLed one too), for ``PE``; None
        #: for the rotary buffer.
        self.prog: int | None = None

    @property
    def v(self) -> dict[str, float]:
        """Velocity of each axis between the blend ramps (units/s)."""
        if self._v is None:
            start, end, tm = self.start, self.end, self.tm
            self._v = {a: (end[a] - start.get(a, 0.0)) / tm for a in end} if tm > 0 else {}
        return self._v

    @property
    def v_prev(self) -> dict[str, float]:
        return self.prev.v if self.prev is not None else {}

    @property
    def blends(self) -> bool:
        """Part of a blended sequence (``??`` word 1 bit 2, continuous motion mode)."""
        return self.kind in _BLENDING


class PlanContext(Protocol):
    """What a mode's ``plan`` function reads from its coordinate system (refreshed by the
    caller before the call): the modal state and the I-variable-derived timings."""

    vars: Variables
    cs: int
    time_mode: bool
    mode: str
    #: The vector-feedrate axes (``FRAX``), default X, Y, Z.
    frax: tuple[str, ...]
    #: ``ABS(R)``: circle centre vectors from the XYZ origin (``INC(R)``, default: from the
    #: move's start point; TSRM p442).
    abs_radius: bool

    @property
    def feedrate(self) -> float:
        """F (Isx89), user units per Isx90 ms."""
        ...

    @property
    def isx90_ms(self) -> float: ...

    @property
    def accel_prog_s(self) -> float:
        """``max(TA, 2·TS)`` in program seconds (before the time-base stretch)."""
        ...

    @property
    def accel_real_s(self) -> float:
        """The same in real seconds (stretched by the ``%`` time base)."""
        ...

    @property
    def special_lookahead(self) -> bool:
        """Isx13 > 0 with a lookahead buffer and Isx20 > 0 (TSRM p98 regime 2)."""
        ...

    @property
    def scurve_prog_s(self) -> float:
        """TS (Isx88) in whole ms, program seconds."""
        ...

    @property
    def time_scale(self) -> float:
        """Real seconds per program second (``100 / %``)."""
        ...

    @property
    def segmented(self) -> bool:
        """Isx13 > 0."""
        ...

    def motors_of(self, axis: str) -> list[tuple[int, float]]:
        """The motors assigned to ``axis`` in this CS and their scales (counts per unit)."""
        ...


class Profile:
    """How one move kind behaves once calculated (the executor's view of a move mode).

    ``blends``: the move is blended with a neighbour of the same ``family`` (no stop
    between); ``breaks``: a lookahead break — it starts from rest, ends in a stop at its
    programmed end, and nothing after it is calculated until it has finished (TUM p341);
    ``decide_at_end``: whether the next move is needed only at this move's end (its decision
    point, as in segmentation mode) rather than when it starts; ``stop_ramp``: a stop at the
    end decelerates over Ta (else the move simply ends at its end point).
    """

    kind: ClassVar[int]
    blends: ClassVar[bool] = False
    family: ClassVar[str] = ""
    breaks: ClassVar[bool] = False
    decide_at_end: ClassVar[bool] = False
    stop_ramp: ClassVar[bool] = True

    def positions(self, m: Move, t: float) -> dict[str, float]:
        """Commanded axis positions at ``t`` (``m`` is the executing move)."""
        raise NotImplementedError

    def velocities(self, m: Move, t: float) -> dict[str, float]:
        """Commanded axis velocities at ``t`` (units/s)."""
        raise NotImplementedError


__all__ = [
    "DELAY", "DWELL", "LINEAR", "PVT", "RAPID", "SPLINE", "Move", "PlanContext", "Profile",
    "RunTimeError",
]  # fmt: skip
