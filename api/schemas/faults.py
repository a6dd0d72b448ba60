"""Injected faults (``/controllers/{id}/faults``): what a fault is once added."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field


class FaultOut(BaseModel):
    """A fault as added (its spec's fields), its id and what it has done so far."""

    model_config = ConfigDict(extra="allow")

    id: str = Field(description="`f1`, `f2`, ... per controller; the `fault` field of its events")
    kind: str
    seen: int = Field(description="matching commands (or BREQ edges) seen since it was added")
    injected: int = Field(description="how many times it took effect")


class FaultList(BaseModel):
    faults: list[FaultOut]


__all__ = ["FaultList", "FaultOut"]
