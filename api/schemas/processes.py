"""Trio BASIC processes."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field


class ProcessOut(BaseModel):
    process: int
    program: str
    state: Literal["running", "blocked", "stopped"]
    line: int = Field(description="program line being executed (the last one once stopped)")
    blocked_on: str | None = Field(None, description="the move line it waits at")
    pmove: int = Field(0, description="PMOVE: 1 while its process buffer holds a move")
    error: str | None = Field(None, description="runtime error that stopped it")


__all__ = ["ProcessOut"]
