"""Events on the wire: ``{"seq", "t", "type", "controller", ...fields}``."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field


class EventOut(BaseModel):
    """One observable change. The fields beyond these depend on ``type`` (API.md's table)."""

    model_config = ConfigDict(extra="allow", json_schema_extra={
        "examples": [{"seq": 12, "t": 0.0125, "type": "breq", "controller": "pmac",
                      "cs": 1, "level": True}]})

    seq: int = Field(description="1, 2, 3 ... per controller")
    t: float = Field(description="simulated seconds")
    type: str
    controller: str


class GapOut(BaseModel):
    """Events ``from`` .. ``to`` left the log's ring before they were read."""

    model_config = ConfigDict(populate_by_name=True)

    type: str = "gap"
    from_: int = Field(alias="from")
    to: int


class ResetOut(BaseModel):
    """The reader's position belonged to another incarnation of the log: start again."""

    epoch: str = Field(description="this log's epoch (the one to resume with from now on)")
    reason: str = Field(description="`stale_epoch` or `since_beyond_end`")
    since: int = Field(description="the `since` asked for")
    last_seq: int = Field(description="the newest seq of this log")


class EventsPage(BaseModel):
    """Events with ``seq > since``; pass ``next`` as ``since`` (and ``epoch``) to continue."""

    epoch: str = Field(description="names this incarnation of the controller's log: `seq` "
                                   "restarts at 1 in a new one (restart, delete + re-create)")
    events: list[EventOut]
    next: int
    gap: GapOut | None = Field(None, description="present when older events were lost")
    reset: ResetOut | None = Field(None, description="present when `epoch` was stale or "
                                   "`since` beyond the log's end: the page starts at the "
                                   "beginning of this log")


__all__ = ["EventOut", "EventsPage", "GapOut", "ResetOut"]
