"""The clock resource: how a controller's simulated time moves."""

from __future__ import annotations

from typing import Any, Literal

from motionsim.api.schemas.events import EventOut
from pydantic import BaseModel, ConfigDict, Field

ClockModeField = Literal["virtual", "realtime"]


class ClockOut(BaseModel):
    """``virtual``: moves only on advance / run-until / terminal replies. ``realtime``:
    simulated time = wall time × ``factor``. ``t`` is simulated seconds."""

    mode: ClockModeField
    factor: float
    paused: bool
    t: float


class ClockIn(BaseModel):
    """A clock for a new controller."""

    model_config = ConfigDict(extra="forbid")

    mode: ClockModeField = "realtime"
    factor: float = Field(1.0, gt=0, allow_inf_nan=False)
    paused: bool = False


class ClockPatch(BaseModel):
    """Change the speed-up ``factor``, pause / resume, or switch ``mode`` (at the current t)."""

    model_config = ConfigDict(extra="forbid")

    factor: float | None = Field(None, gt=0, allow_inf_nan=False)
    paused: bool | None = None
    mode: ClockModeField | None = None


class AdvanceIn(BaseModel):
    """Run a virtual clock forward by ``seconds`` of simulated time (0 is a no-op)."""

    model_config = ConfigDict(extra="forbid")

    seconds: float = Field(ge=0, allow_inf_nan=False)


class EventPattern(BaseModel):
    """An event to wait for: its ``type`` and any fields that must be equal."""

    model_config = ConfigDict(extra="allow", json_schema_extra={
        "examples": [{"type": "breq", "cs": 1, "level": True}]})

    type: str

    def as_pattern(self) -> dict[str, Any]:
        return {"type": self.type, **(self.model_extra or {})}


class RunUntilIn(BaseModel):
    """Wait for the first new event matching ``event``, at most ``timeout_s`` simulated."""

    model_config = ConfigDict(extra="forbid")

    event: EventPattern
    timeout_s: float = Field(ge=0, allow_inf_nan=False)


class RunUntilOut(BaseModel):
    matched: EventOut | None
    clock: ClockOut


__all__ = ["AdvanceIn", "ClockIn", "ClockOut", "ClockPatch", "EventPattern", "RunUntilIn",
           "RunUntilOut"]
