"""The clock resource: how a controller's simulated time moves."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field

from ...sim.bounds import ADVANCE_SECONDS, CLOCK_FACTOR, TIMEOUT_SECONDS
from .events import EventOut

ClockModeField = Literal["virtual", "realtime", "host-paced"]

HolderName = Annotated[str, Field(pattern=r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,63}$",
                                  description="a client taking part in host pacing")]
ReactionS = Annotated[float, Field(ge=0, le=60, allow_inf_nan=False, description=(
    "host-paced: simulated seconds between the event a holder waits for and the instant it "
    "acts (its host's reaction time)"))]


def _Only(description: str) -> Any:  # noqa: N802 - reads as a field type
    """A field only some clock modes have: absent (not null) on the others."""
    return Field(None, description=description, exclude_if=lambda v: v is None)


class HolderOut(BaseModel):
    """A host-paced clock's holder: ``acting`` (time stands still for it) or ``waiting``."""

    name: str
    state: Literal["acting", "waiting"]
    since_t: float = Field(description="simulated instant it began acting / waiting")
    event: dict[str, Any] | None = Field(None, description="the pattern it waits for")
    until_t: float | None = Field(None, description="the simulated deadline of its wait")


class ClockOut(BaseModel):
    """``virtual``: moves only on advance / run-until / terminal replies. ``realtime``:
    simulated time = wall time × ``factor``. ``host-paced``: moves as fast as the CPU allows
    while every holder waits, holds where one is due. ``t`` is simulated seconds."""

    mode: ClockModeField
    factor: float
    paused: bool
    t: float
    lag_s: float | None = _Only("realtime: wall seconds the simulation is behind its schedule "
                                "(0 when it keeps up)")
    behind: bool | None = _Only("realtime: lag above 0.1 s (a `clock_lag` event marks each "
                                "change)")
    slipped_s: float | None = _Only("realtime: simulated seconds given up so far to stay within "
                                    "0.5 s of the schedule")
    reaction_s: float | None = _Only("host-paced: the hosts' reaction time")
    holders: list[HolderOut] | None = _Only("host-paced: its holders")
    held_by: list[str] | None = _Only("host-paced: the holders acting now (time stands still "
                                      "for them)")


class ClockIn(BaseModel):
    """A clock for a new controller."""

    model_config = ConfigDict(extra="forbid", strict=True)

    mode: ClockModeField = "realtime"
    factor: float = Field(1.0, ge=CLOCK_FACTOR.low, le=CLOCK_FACTOR.high, allow_inf_nan=False,
                          description="simulated seconds per wall second (realtime)")
    paused: bool = False
    reaction_s: ReactionS = 0.0
    holders: list[HolderName] | None = Field(None, max_length=64, description=(
        "host-paced: holders registered acting at once (time waits for their first call)"))


class ClockPatch(BaseModel):
    """Change the speed-up ``factor``, pause / resume, or switch ``mode`` (at the current t)."""

    model_config = ConfigDict(extra="forbid", strict=True)

    factor: float | None = Field(None, ge=CLOCK_FACTOR.low, le=CLOCK_FACTOR.high,
                                 allow_inf_nan=False)
    paused: bool | None = None
    mode: ClockModeField | None = None
    reaction_s: ReactionS | None = None
    holders: list[HolderName] | None = Field(None, max_length=64, description=(
        "host-paced: holders to register (acting at the current instant)"))


class AdvanceIn(BaseModel):
    """Run a virtual clock forward by ``seconds`` of simulated time (0 is a no-op)."""

    model_config = ConfigDict(extra="forbid", strict=True)

    seconds: float = Field(ge=ADVANCE_SECONDS.low, le=ADVANCE_SECONDS.high, allow_inf_nan=False,
                           description="simulated seconds")
    holder: HolderName | None = Field(None, description=(
        "host-paced: the holder that waits (default `main`)"))


class EventPattern(BaseModel):
    """An event to wait for: its ``type`` and any fields that must be equal."""

    model_config = ConfigDict(extra="allow", json_schema_extra={
        "examples": [{"type": "breq", "cs": 1, "level": True}]})

    type: str = Field(min_length=1, max_length=64,
                      description="an event type the controller emits (422 otherwise)")

    def as_pattern(self) -> dict[str, Any]:
        return {"type": self.type, **(self.model_extra or {})}


class RunUntilIn(BaseModel):
    """Wait for the first new event matching ``event``, at most ``timeout_s`` simulated."""

    model_config = ConfigDict(extra="forbid", strict=True)

    event: EventPattern
    timeout_s: float = Field(ge=TIMEOUT_SECONDS.low, le=TIMEOUT_SECONDS.high,
                             allow_inf_nan=False, description="simulated seconds")
    holder: HolderName | None = Field(None, description=(
        "host-paced: the holder that waits (default `main`)"))


class RunUntilOut(BaseModel):
    matched: EventOut | None
    clock: ClockOut
    outcome: Literal["matched", "timeout", "wall_timeout", "released"] = Field(
        "matched", description=(
            "`timeout`: `timeout_s` of simulated time passed; `wall_timeout`: the wall cap "
            "(30 s) passed first; `released`: host-paced, its holder was released"))


__all__ = ["AdvanceIn", "ClockIn", "ClockOut", "ClockPatch", "EventPattern", "HolderOut",
           "RunUntilIn", "RunUntilOut"]
