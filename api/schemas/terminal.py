"""The terminal: the controller's own command line, one line per POST."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field


class TerminalIn(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True, json_schema_extra={
        "examples": [{"command": "&1 B0 R"}, {"command": "PRINT MTYPE AXIS(0)"}]})

    command: str = Field(max_length=4096, description="one line exactly as typed")


class TerminalOut(BaseModel):
    """``reply``: the data lines joined with ``\\r`` (no ACK); ``error``: the controller's error
    (``ERR003``) — still HTTP 200; ``pending``: no reply yet, it will come as a
    ``terminal_reply`` event."""

    reply: str
    error: str | None
    pending: bool
    error_meaning: str | None = Field(
        default=None, description="PMAC: the Turbo SRM meaning of the ERRnnn in `error`")
    not_simulated: bool = Field(
        default=False,
        description="the command is valid on the real controller but motionsim does not "
        "simulate it (the wire still answers the controller's error code)")
    detail: str | None = Field(
        default=None, description="what was wrong and where (column), or what is not simulated")
    output: list[str] = Field(
        default_factory=list,
        description="Trio: lines a program printed on channel 0 (the command line) since the "
        "REST terminal's previous command, oldest first; PMAC: the SEND lines of its PLCs and "
        "motion programs since then, whatever their port; the key is present only when there "
        "are some",
    )


class TerminalState(BaseModel):
    """A Trio terminal locked on a move that cannot be buffered, and the commands behind it."""

    locked: bool
    pending: list[str]


__all__ = ["TerminalIn", "TerminalOut", "TerminalState"]
