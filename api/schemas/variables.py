"""Controller variables by their controller names: PMAC ``I16``, ``P5``, ``Q1``, ``M1``;
Trio ``VR(5)``."""

from __future__ import annotations

import math

from pydantic import BaseModel, ConfigDict, Field, RootModel, StrictFloat, field_validator


class VariableOut(BaseModel):
    name: str = Field(description="upper case, as the controller names it")
    value: float


class VariableIn(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True)

    value: float = Field(allow_inf_nan=False)


#: Most variables one bulk write may set.
MAX_BULK = 4096


class VariablesIn(RootModel[dict[str, StrictFloat]]):
    """A map of variable name → value (numbers; not strings or booleans), written in one
    request in the order given."""

    root: dict[str, StrictFloat] = Field(min_length=1, max_length=MAX_BULK,
                                         examples=[{"I16": 5, "I17": 10, "P1": 2.5}],
                                         json_schema_extra={"propertyNames": {
                                             "minLength": 1, "maxLength": 64}})

    @field_validator("root")
    @classmethod
    def _finite(cls, values: dict[str, float]) -> dict[str, float]:
        for name, value in values.items():
            if not math.isfinite(value):
                raise ValueError(f"{name}: value must be finite")
        return values


class VariablesOut(BaseModel):
    values: dict[str, float] = Field(description="name (upper case) → value after the write")


__all__ = ["MAX_BULK", "VariableIn", "VariableOut", "VariablesIn", "VariablesOut"]
