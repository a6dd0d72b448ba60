"""Trio programs: stored by name, run in a process."""

from __future__ import annotations

from motionsim.api.schemas.common import Int
from pydantic import BaseModel, ConfigDict, Field


class ProgramStored(BaseModel):
    name: str = Field(description="upper case, as the controller names it")
    lines: int


class ProgramList(BaseModel):
    programs: list[str]


class RunIn(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True)

    process: Int | None = Field(None, ge=1, description="default: the highest free process")


class RunOut(BaseModel):
    process: int


__all__ = ["ProgramList", "ProgramStored", "RunIn", "RunOut"]
