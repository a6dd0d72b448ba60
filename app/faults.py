"""Seeded fault injection per controller, so host authors can exercise their retry paths.

A fault is a :data:`FaultSpec` (validated strictly: an impossible value is refused with the
field named, and nothing changes) added to the controller's :class:`FaultTable` through
``POST /controllers/{id}/faults`` or a scenario's ``faults:``. Kinds:

* on the link (the controllers' TCP protocols: PMAC Ethernet, the Trio command line) —
  ``reply_delay`` (the reply leaves ``delay_ms`` of wall time late), ``reply_drop`` (the
  command runs, its reply is never sent), ``connection_reset`` (``after_bytes`` of the reply
  are sent, then the connection is reset);
* on the command line (TCP and the REST terminal) — ``error_reply``: a PMAC answers
  ``ERRnnn`` and does not execute the command;
* inside the card (:mod:`motionsim.sim.faults`) — ``stall`` (the background starved for
  ``duration_ms`` of simulated time), ``breq_lost`` (a rising BREQ edge not signalled).

Command faults pick commands by ``match`` (a regular expression searched in the command line,
case-insensitive, by the linear-time matcher of :mod:`motionsim.app.fault_match`: a pattern
that needs backtracking is refused; every command if omitted): the ``nth`` matching command
and the ones after it are hit, each with ``probability``, ``count`` times at most. Draws come
from the fault's own ``random.Random(seed)``, made only for commands it may hit, so the same
commands and seed hit the same ones. Every injection is a ``fault`` event (``fault`` = the
fault's id, ``kind``, and ``command`` / ``cs`` / ``start_s`` and ``end_s``) at the simulated
instant it happens.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass
from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field, TypeAdapter, field_validator

from ..sim.errors import InvalidValue, NotFound
from ..sim.faults import EdgeLoss, Selector
from .fault_match import CommandPattern

#: Faults one controller may hold at once.
MAX_FAULTS = 64


class _Spec(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True)

    seed: int = Field(0, ge=0, le=2**63 - 1, description="seeds this fault's own draws")


class _CommandSpec(_Spec):
    match: str | None = Field(None, min_length=1, max_length=200,
                              description="regular expression (RE2 syntax: no back-references "
                                          "or look-around) searched in the command line "
                                          "(case-insensitive) in linear time; every "
                                          "command if omitted")
    nth: int = Field(1, ge=1, le=10**9, description="the first matching command hit")
    count: int | None = Field(1, ge=1, le=10**9, description="most injections (null: no limit)")
    probability: float = Field(1.0, gt=0.0, le=1.0, allow_inf_nan=False,
                               description="chance per eligible command")

    @field_validator("match")
    @classmethod
    def _compiles(cls, value: str | None) -> str | None:
        if value is not None:
            CommandPattern(value)
        return value


class ReplyDelay(_CommandSpec):
    """The reply to a matching command leaves ``delay_ms`` (wall time) late."""

    kind: Literal["reply_delay"]
    delay_ms: float = Field(gt=0, le=60_000, allow_inf_nan=False)


class ReplyDrop(_CommandSpec):
    """A matching command is executed; its reply is never sent."""

    kind: Literal["reply_drop"]


class ConnectionReset(_CommandSpec):
    """``after_bytes`` of the reply are sent (half of it if omitted), then a reset."""

    kind: Literal["connection_reset"]
    after_bytes: int | None = Field(None, ge=0, le=1_000_000)


class ErrorReply(_CommandSpec):
    """A PMAC answers ``error`` (``ERR003`` ...) to a matching command and does not run it."""

    kind: Literal["error_reply"]
    error: str = Field(pattern=r"^ERR\d{3}$", description="the ERRnnn answered")


class Stall(_Spec):
    """The card's background gets no processor time for ``duration_ms`` of simulated time,
    from ``at_ms`` after the fault is added (PMAC)."""

    kind: Literal["stall"]
    at_ms: float = Field(0.0, ge=0, le=86_400_000, allow_inf_nan=False)
    duration_ms: float = Field(gt=0, le=600_000, allow_inf_nan=False)


class BreqLost(_Spec):
    """Rising BREQ edges of ``cs`` (every CS if omitted) are not signalled (PMAC)."""

    kind: Literal["breq_lost"]
    cs: int | None = Field(None, ge=1, le=16)
    nth: int = Field(1, ge=1, le=10**9)
    count: int | None = Field(1, ge=1, le=10**9)
    probability: float = Field(1.0, gt=0.0, le=1.0, allow_inf_nan=False)


FaultSpec = Annotated[ReplyDelay | ReplyDrop | ConnectionReset | ErrorReply | Stall | BreqLost,
                      Field(discriminator="kind")]
FAULT_SPEC: TypeAdapter[Any] = TypeAdapter(FaultSpec)

#: Kinds that act on the link (TCP replies); the rest act on the command or in the card.
LINK_KINDS = frozenset({"reply_delay", "reply_drop", "connection_reset"})
#: Kinds only a PMAC has.
PMAC_KINDS = frozenset({"error_reply", "stall", "breq_lost"})


@dataclass(frozen=True, slots=True)
class ReplyAction:
    """What the link does with the next reply: ``kind`` and its parameters."""

    fault: str
    kind: str
    delay_s: float = 0.0
    after_bytes: int | None = None


class _CommandFault:
    """A command fault: its spec, its pattern, and which matching commands it takes."""

    def __init__(self, id: str, spec: Any) -> None:
        self.id = id
        self.spec = spec
        self.pattern = CommandPattern(spec.match) if spec.match else None
        self.select = Selector(spec.nth, spec.count, spec.probability, spec.seed)

    def hits(self, command: str) -> bool:
        if self.pattern is not None and not self.pattern.search(command):
            return False
        return self.select.take()


class FaultTable:
    """The faults of one controller, in the order added.

    Args:
        controller: the simulated controller (its ``kind``, ``log``, and for a PMAC its
            ``card_faults`` and ``background``).
    """

    def __init__(self, controller: Any) -> None:
        self.controller = controller
        self._faults: dict[str, Any] = {}  # id -> _CommandFault | (spec, EdgeLoss | None)
        self._next = 1

    # -- the resource ----------------------------------------------------------------------

    def add(self, spec: Any) -> dict[str, Any]:
        """Validate ``spec`` against this controller and add it; returns its description.

        Raises:
            InvalidValue: a kind this controller does not have, or too many faults.
        """
        kind = spec.kind
        ctl = self.controller
        if kind in PMAC_KINDS and getattr(ctl, "kind", "") != "pmac":
            raise InvalidValue(f"a {getattr(ctl, 'kind', '?')} controller has no {kind} fault "
                               f"(PMAC only)", field="kind")
        if len(self._faults) >= MAX_FAULTS:
            raise InvalidValue(f"at most {MAX_FAULTS} faults per controller", field="kind")
        id = f"f{self._next}"
        self._next += 1
        if kind == "stall":
            start = ctl.now + spec.at_ms / 1000.0
            end = start + spec.duration_ms / 1000.0
            ctl.background.stall(start, end)
            ctl.log.emit("fault", fault=id, kind=kind, start_s=start, end_s=end)
            self._faults[id] = (spec, None)
        elif kind == "breq_lost":
            loss = EdgeLoss(id, spec.cs,
                            Selector(spec.nth, spec.count, spec.probability, spec.seed))
            ctl.card_faults.add_edge_loss(loss)
            self._faults[id] = (spec, loss)
        else:
            self._faults[id] = _CommandFault(id, spec)
        return self.describe(id)

    def describe(self, id: str) -> dict[str, Any]:
        entry = self._faults[id]
        if isinstance(entry, _CommandFault):
            spec, seen, injected = entry.spec, entry.select.seen, entry.select.injected
        else:
            spec, loss = entry
            seen = loss.select.seen if loss is not None else 0
            injected = loss.select.injected if loss is not None else 1
        return {"id": id, **spec.model_dump(), "seen": seen, "injected": injected}

    def list(self) -> list[dict[str, Any]]:
        return [self.describe(id) for id in self._faults]

    def remove(self, id: str) -> None:
        """Forget fault ``id`` (a stall already under way is ended now); raises NotFound."""
        if id not in self._faults:
            raise NotFound(f"no fault {id!r}; set: {', '.join(self._faults) or 'none'}")
        entry = self._faults.pop(id)
        if isinstance(entry, tuple):
            spec, _ = entry
            if spec.kind == "breq_lost":
                self.controller.card_faults.remove(id)
            elif spec.kind == "stall":
                now = self.controller.now
                self.controller.background.stall(now, now)

    def clear(self) -> None:
        for id in list(self._faults):
            self.remove(id)

    # -- decisions -------------------------------------------------------------------------

    def _command_faults(self, kinds: frozenset[str]) -> list[_CommandFault]:
        return [f for f in self._faults.values()
                if isinstance(f, _CommandFault) and f.spec.kind in kinds]

    def forced_error(self, command: str) -> str | None:
        """The ``ERRnnn`` a matching ``error_reply`` fault answers ``command`` with, or None."""
        for fault in self._command_faults(frozenset({"error_reply"})):
            if fault.hits(command):
                self._log(fault, command)
                return fault.spec.error
        return None

    def reply_action(self, command: str) -> ReplyAction | None:
        """What the link does with the reply to ``command`` (None: send it as usual)."""
        for fault in self._command_faults(LINK_KINDS):
            if fault.hits(command):
                self._log(fault, command)
                spec = fault.spec
                if spec.kind == "reply_delay":
                    return ReplyAction(fault.id, spec.kind, delay_s=spec.delay_ms / 1000.0)
                if spec.kind == "connection_reset":
                    return ReplyAction(fault.id, spec.kind, after_bytes=spec.after_bytes)
                return ReplyAction(fault.id, spec.kind)
        return None

    def _log(self, fault: _CommandFault, command: str) -> None:
        extra = {"error": fault.spec.error} if fault.spec.kind == "error_reply" else {}
        self.controller.log.emit("fault", fault=fault.id, kind=fault.spec.kind,
                                 command=command, **extra)


_TABLES: weakref.WeakKeyDictionary[Any, FaultTable] = weakref.WeakKeyDictionary()


def faults_of(controller: Any) -> FaultTable:
    """The :class:`FaultTable` of ``controller`` (created empty on first use)."""
    table = _TABLES.get(controller)
    if table is None:
        table = _TABLES[controller] = FaultTable(controller)
    return table


def has_faults(controller: Any) -> bool:
    """True when ``controller`` has a fault table with anything in it (the hooks' fast path)."""
    table = _TABLES.get(controller)
    return table is not None and bool(table._faults)


__all__ = ["FAULT_SPEC", "LINK_KINDS", "MAX_FAULTS", "PMAC_KINDS", "BreqLost",
           "ConnectionReset", "ErrorReply", "FaultSpec", "FaultTable", "ReplyAction",
           "ReplyDelay", "ReplyDrop", "Stall", "faults_of", "has_faults"]
