"""Trio programs: stored by name, run in a process."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field

from .common import int_in


class ProgramStored(BaseModel):
    name: str = Field(description="upper case, as the controller names it")
    lines: int


class ProgramList(BaseModel):
    programs: list[str]


class RunIn(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True)

    process: int_in(1, 32) | None = Field(  # type: ignore[valid-type]
        None, description="1..the controller's processes (at most 32; 422 beyond); default: "
                          "the highest free process")


class RunOut(BaseModel):
    process: int


__all__ = ["ProgramList", "ProgramStored", "RunIn", "RunOut"]
