"""The controller resource."""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, ConfigDict, Field

from ...sim.bounds import (
    PMAC_CONFIG,
    PMAC_CPU_COST,
    TRIO_CONFIG,
    TRIO_RATE,
    TRIO_UNITS,
    describe,
)
from .clock import ClockIn, ClockOut

CONFIG_DOC = (
    "the kind's initial settings; unknown keys and values outside these bounds are 422. "
    f"PMAC: {describe(PMAC_CONFIG)}; cpu_<task>_us: {PMAC_CPU_COST.describe()}; "
    "iN (I-variables): finite. "
    f"Trio: {describe(TRIO_CONFIG)}; speed, accel, decel, creep: "
    f"{TRIO_RATE.describe()}; units: {TRIO_UNITS.describe()}.")


class ControllerOut(BaseModel):
    """A running controller; the kind's own status (e.g. PMAC ``cpu``) is merged in."""

    model_config = ConfigDict(extra="allow")

    id: str
    kind: str
    clock: ClockOut


class ControllerIn(BaseModel):
    """A new controller. ``config`` holds the kind's initial settings, e.g. PMAC
    ``{"i16": 5, "i17": 10, "i8": 2, "servo_hz": 2258.0}`` or Trio ``{"servo_period_ms": 1.0}``."""

    model_config = ConfigDict(extra="forbid", strict=True, json_schema_extra={
        "examples": [{"id": "pmac2", "kind": "pmac", "clock": {"mode": "virtual"},
                      "config": {"i16": 5, "i17": 10}}]})

    id: str | None = Field(None, pattern=r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,63}$",
                           description="default: kind + a number")
    kind: str = Field(min_length=1, max_length=64,
                      description="an installed kind: pmac, trio, ... (422 otherwise)")
    clock: ClockIn = Field(default_factory=ClockIn)
    config: dict[str, Any] = Field(default_factory=dict, description=CONFIG_DOC)


__all__ = ["ControllerIn", "ControllerOut"]
