"""Controller variables by their controller names: PMAC ``I16``, ``P5``, ``Q1``, ``M1``;
Trio ``VR(5)``."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field


class VariableOut(BaseModel):
    name: str = Field(description="upper case, as the controller names it")
    value: float


class VariableIn(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True)

    value: float = Field(allow_inf_nan=False)


__all__ = ["VariableIn", "VariableOut"]
