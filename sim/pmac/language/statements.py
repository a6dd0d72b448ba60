"""Typed statements of the Turbo PMAC command language.

The parser (:mod:`motionsim.sim.pmac.language.parser`) turns text into these values; the terminal
and the
coordinate systems execute them. Two families:

* **on-line commands** act when received (addressing ``&n``/``#n``, buffer management,
  ``R``/``Q``/``A``, queries);
* **program statements** are what a motion program is made of (moves, modal settings, dwells,
  assignments). With a buffer open they are stored; with buffers closed an assignment executes
  at once and the others are refused with ERR005 (TUM p46).
"""

from __future__ import annotations

from dataclasses import dataclass

from .axis_definitions import AxisDefinition, Frax
from .expressions import Expr
from .flow_statements import FLOW_TYPES
from .motor_statements import HomeList
from .plc_idioms import Address
from .ranges import RangeAssign

# -- on-line commands -------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class AddressCS:
    """``&n`` selects the coordinate system for later commands on this port; ``&`` reports it."""

    cs: int | None


@dataclass(frozen=True, slots=True)
class AddressMotor:
    """``#n`` selects the motor; ``#`` reports it."""

    motor: int | None


@dataclass(frozen=True, slots=True)
class DefineRotary:
    """``DEFINE ROT n``: a rotary buffer of ``n`` words for the addressed CS."""

    words: int


@dataclass(frozen=True, slots=True)
class DeleteRotary:
    """``DELETE ROT``: erase the addressed CS's rotary buffer."""


@dataclass(frozen=True, slots=True)
class DefineGather:
    """``DEFINE GATHER [n]``: with no size it takes all free buffer memory."""

    words: int | None


@dataclass(frozen=True, slots=True)
class DeleteGather:
    """``DELETE GATHER``."""


@dataclass(frozen=True, slots=True)
class Gather:
    """``GATHER`` (``GAT``): start data gathering at the next servo cycle; ``GATHER
    TRIGGER``: at the servo cycle that finds the gathering trigger input risen
    (:mod:`motionsim.sim.pmac.tasks.gather`)."""

    trigger: bool = False


@dataclass(frozen=True, slots=True)
class EndGather:
    """``ENDGATHER`` (``ENDG``, ``END GATHER``): stop data gathering."""


@dataclass(frozen=True, slots=True)
class DefineLookahead:
    """``DEFINE LOOKAHEAD segs,outputs``: the addressed CS's special lookahead buffer."""

    segments: int
    outputs: int


@dataclass(frozen=True, slots=True)
class DeleteLookahead:
    """``DELETE LOOKAHEAD``: erase the addressed CS's lookahead buffer."""


@dataclass(frozen=True, slots=True)
class OpenRotary:
    """``OPEN ROT``: open every defined rotary buffer for entry."""


@dataclass(frozen=True, slots=True)
class OpenProgram:
    """``OPEN PROG n``: open fixed motion program ``n`` for entry."""

    n: int


@dataclass(frozen=True, slots=True)
class Close:
    """``CLOSE``: stop entry into the open buffers (execution goes on)."""


@dataclass(frozen=True, slots=True)
class ProgramPointer:
    """``B{n}`` with buffers closed: point the CS at program ``n`` (0 = its rotary buffer)."""

    program: float


@dataclass(frozen=True, slots=True)
class Run:
    """``R``: run from the program pointer, continuous."""


@dataclass(frozen=True, slots=True)
class Step:
    """``S``: run one move and stop."""


@dataclass(frozen=True, slots=True)
class Quit:
    """``Q``: stop after the moves already calculated."""


@dataclass(frozen=True, slots=True)
class StopAtEnd:
    """``/``: stop at the end of the move executing now (TUM p217 "end of currently
    executing move, undoes blending"; with Isx13 = 0 it acts as ``Q``, TSRM p177)."""


@dataclass(frozen=True, slots=True)
class QuickStop:
    """``\\``: quick stop in the special lookahead; outside lookahead (and with Isx13 = 0) it
    acts as ``H`` (TUM p217; TSRM p177, p181: Isx21 = 4 is the same request)."""


@dataclass(frozen=True, slots=True)
class Abort:
    """``A``: break into the trajectory now, decelerate, discard lookahead and sync writes."""


@dataclass(frozen=True, slots=True)
class MFlush:
    """``MFLUSH``: empty the addressed CS's synchronous M-variable queue (TUM p250)."""


@dataclass(frozen=True, slots=True)
class Hold:
    """``H``: feed hold."""


@dataclass(frozen=True, slots=True)
class Query:
    """A report: ``PR``, ``??``, ``?``, ``???``, ``SIZE``, ``VER``, ``CID``, ``TYPE``, ``CPU``,
    ``VID``, and the motor reports ``P`` ``V`` ``F``."""

    what: str


@dataclass(frozen=True, slots=True)
class ProgramCounter:
    """``PC`` (``executing`` False) or ``PE`` (``executing`` True): where the addressed CS's
    program counter points (:mod:`motionsim.sim.pmac.host.program_counter`)."""

    executing: bool


@dataclass(frozen=True, slots=True)
class FeedOverride:
    """``%{n}`` sets the addressed CS's feedrate override (``%`` alone reports it)."""

    percent: float


@dataclass(frozen=True, slots=True)
class VarQuery:
    """``I16``, ``I16..17`` (``last``), ``I130,4,100`` (``count``, ``step``); also P, Q, M."""

    kind: str
    first: int
    last: int | None = None
    count: int | None = None
    step: int | None = None

    def numbers(self) -> list[int]:
        if self.last is not None:
            return list(range(self.first, self.last + 1))
        if self.count is not None:
            return [self.first + i * (self.step or 1) for i in range(self.count)]
        return [self.first]


@dataclass(frozen=True, slots=True)
class VarDefault:
    """``I16=*`` / ``I16..17=*``: the manufacturer's default (TUM p243)."""

    first: int
    last: int


@dataclass(frozen=True, slots=True)
class MDefinitionQuery:
    """``M1->`` / ``M1..10->``: report M-variable definitions (``last`` None: just ``n``);
    ``kind`` ``"L"`` for the L-variables of compiled PLCs."""

    n: int
    last: int | None = None
    kind: str = "M"

    def numbers(self) -> range:
        return range(self.n, (self.n if self.last is None else self.last) + 1)


# -- program statements -----------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class VarRef:
    """A variable target ``P1`` or ``P(P2+1)``; ``kind`` is I, P, Q or M."""

    kind: str
    index: Expr


@dataclass(frozen=True, slots=True)
class Assign:
    """``P1=expr``; ``op`` is ``=`` or a synchronous form ``==`` ``&=`` ``|=`` ``^=`` (M only)."""

    target: VarRef
    op: str
    value: Expr

    @property
    def synchronous(self) -> bool:
        return self.op != "="


@dataclass(frozen=True, slots=True)
class MoveMode:
    """``LINEAR``, ``RAPID``, ``CIRCLE1``, ``CIRCLE2``, ``SPLINE1``, ``SPLINE2``."""

    mode: str


@dataclass(frozen=True, slots=True)
class PvtMode:
    """``PVT{t}``: PVT move mode with segment time ``t`` ms (written where ``TM`` writes, the
    move-time register; TSRM p463)."""

    ms: Expr


@dataclass(frozen=True, slots=True)
class PSet:
    """``PSET{axis}{data}[{axis}{data}...]``: make the present positions of these axes the
    given values, without motion (TSRM p31, TUM p341, PSRM p340); a lookahead break."""

    axes: tuple[tuple[str, Expr], ...]


@dataclass(frozen=True, slots=True)
class AxisMode:
    """``INC`` / ``ABS`` [``(X,Y)``]; ``axes`` None = all axes."""

    incremental: bool
    axes: tuple[str, ...] | None


@dataclass(frozen=True, slots=True)
class Modal:
    """``TA`` ``TS`` ``TM`` ``F`` with a value (ms, ms, ms, units per Isx90 ms)."""

    name: str
    value: Expr


@dataclass(frozen=True, slots=True)
class AxisWord:
    """``X10``, ``B0`` (buffer open), ``Z(P1*2)``; ``X10:5`` (PVT) gives an end velocity."""

    axis: str
    value: Expr
    velocity: Expr | None = None


@dataclass(frozen=True, slots=True)
class VectorWord:
    """Circle centre vector ``I`` ``J`` ``K`` or radius ``R`` of a move."""

    name: str
    value: Expr


@dataclass(frozen=True, slots=True)
class Dwell:
    """``DWELL t``: stop, hold t ms (real time); stops lookahead."""

    ms: Expr


@dataclass(frozen=True, slots=True)
class Delay:
    """``DELAY t``: a zero-distance move of t ms, calculated through."""

    ms: Expr


@dataclass(frozen=True, slots=True)
class Label:
    """``N100`` / ``O100`` line labels (stored, no action)."""

    kind: str
    n: int


@dataclass(frozen=True, slots=True)
class Message:
    """``SEND{port}"..."`` / ``CMD{port}"..."`` in a motion program: a ``SEND`` line goes to
    the host when the line is calculated (sim.pmac.host.messages); a ``CMD`` is stored and
    takes no action there."""

    kind: str
    text: str
    port: str = ""


OnlineStatement = (
    AddressCS
    | AddressMotor
    | AxisDefinition
    | DefineRotary
    | DeleteRotary
    | DefineGather
    | DeleteGather
    | Gather
    | EndGather
    | OpenRotary
    | Close
    | ProgramPointer
    | Run
    | Step
    | Quit
    | Abort
    | Hold
    | Query
    | FeedOverride
    | VarQuery
    | VarDefault
    | MDefinitionQuery
)

ProgramStatement = (
    Assign
    | MoveMode
    | PvtMode
    | AxisMode
    | Modal
    | AxisWord
    | VectorWord
    | Dwell
    | Delay
    | PSet
    | Label
    | Message
)

#: Statement types that are program statements (stored when a buffer is open).
PROGRAM_TYPES = (
    Frax,
    Address,
    RangeAssign,
    Assign,
    MoveMode,
    PvtMode,
    AxisMode,
    Modal,
    AxisWord,
    VectorWord,
    Dwell,
    Delay,
    PSet,
    HomeList,
    Label,
    Message,
    *FLOW_TYPES,
)

AXES = "XYZABCUVW"
