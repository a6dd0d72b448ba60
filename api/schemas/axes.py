"""Trio axes: the axis resource, its writable parameters, and a move request."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field

from ...sim.bounds import TRIO_DISTANCE, TRIO_RATE, TRIO_UNITS
from .common import int_in


class AxisOut(BaseModel):
    """One axis: its move buffers (MTYPE / NTYPE codes, 0 = idle), positions and parameters."""

    axis: int
    mtype: int = Field(description="code of the move executing: 0 idle, 1 MOVE, 2 MOVEABS, "
                                   "3 MHELICAL, 4 MOVECIRC, 10 FORWARD, 11 REVERSE, 12 DATUM")
    ntype: int = Field(description="code of the move waiting in NTYPE (0 = empty)")
    dpos: float = Field(description="demand position, user units")
    mpos: float = Field(description="measured position: dpos - fe (= dpos with fe_lag 0)")
    endmove: float = Field(description="end position of the executing move")
    remain: float = Field(description="path distance still to go in the executing move")
    speed: float
    accel: float
    decel: float
    units: float = Field(description="encoder edges per user unit")
    creep: float | None = None
    vp_speed: float | None = Field(None, description="profile generator speed now")
    moves_buffered: int | None = Field(None, description="MTYPE and NTYPE slots in use")
    merge: float | None = Field(None, description="MERGE: 1 = ON (no ramp down into a loaded "
                                                  "next move), 0 = OFF")
    sramp: float | None = Field(None, description="SRAMP: S-ramp time in ms (0 = trapezoid)")
    fe: float | None = Field(None, description="FE = dpos - mpos, the following error of the "
                                               "servo model (0 with fe_lag 0)")
    fe_lag: float | None = Field(None, description="the simulated servo's lag, s: FE = fe_lag "
                                                   "x the demand speed (docs/trio.md)")


class AxisPatch(BaseModel):
    """Parameters to write; all are checked before any is written."""

    model_config = ConfigDict(extra="forbid", strict=True)

    speed: float | None = Field(None, gt=0, le=TRIO_RATE.high, allow_inf_nan=False)
    accel: float | None = Field(None, gt=0, le=TRIO_RATE.high, allow_inf_nan=False)
    decel: float | None = Field(None, gt=0, le=TRIO_RATE.high, allow_inf_nan=False)
    units: float | None = Field(None, ge=TRIO_UNITS.low, le=TRIO_UNITS.high,
                                allow_inf_nan=False)
    creep: float | None = Field(None, gt=0, le=TRIO_RATE.high, allow_inf_nan=False)
    merge: float | None = Field(None, allow_inf_nan=False, description="non-zero = ON")
    sramp: float | None = Field(None, ge=0, le=250, allow_inf_nan=False, description="ms")
    fe_lag: float | None = Field(None, ge=0, le=1, allow_inf_nan=False,
                                 description="s: the following-error model's lag (0 = none)")


#: A move argument: finite and within ±1e12 user units (sim/bounds.py).
Distance = Annotated[float, Field(ge=TRIO_DISTANCE.low, le=TRIO_DISTANCE.high,
                                  allow_inf_nan=False)]

MoveType = Literal["MOVE", "MOVEABS", "MOVECIRC", "MHELICAL", "FORWARD", "REVERSE", "DATUM"]


class MoveIn(BaseModel):
    """A motion command with the path axis as its base axis (multi-axis commands drive the
    axes after it: ``MOVE`` with 2 args on axis 0 drives axes 0 and 1)."""

    model_config = ConfigDict(extra="forbid", strict=True)

    type: MoveType
    args: list[Distance] = Field(default_factory=list, max_length=16,
                                 description="distances / positions, user units")
    process: int_in(0, 32) | None = Field(  # type: ignore[valid-type]
        None, description="issuing process (default 0, the command line; at most 32)")


class MovePlaced(BaseModel):
    placed: Literal["mtype", "ntype", "process_buffer"]


__all__ = ["AxisOut", "AxisPatch", "MoveIn", "MovePlaced", "MoveType"]
