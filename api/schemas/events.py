"""Events on the wire: ``{"seq", "t", "type", "controller", ...fields}``."""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from ...sim.errors import InvalidValue


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


class StreamQuery(BaseModel):
    """The WebSocket's query, validated after the handshake (a bad one: close 4422)."""

    model_config = ConfigDict(extra="ignore")

    since: int = Field(0, ge=0, le=2**63 - 1, description="send events with seq > since")
    type: list[str] | None = Field(None, description="only these types (repeatable)")
    batch: bool = Field(False, description="each message a JSON array of events")
    epoch: str | None = Field(None, max_length=64, description="the epoch `since` came from")


def stream_query(params: Any) -> StreamQuery:
    """:class:`StreamQuery` from a ``QueryParams`` (``type`` repeatable, the rest single).

    Raises:
        InvalidValue: naming the first bad field and what was wrong with it.
    """
    data: dict[str, Any] = {k: params.get(k) for k in ("since", "batch", "epoch") if k in params}
    if "type" in params:
        data["type"] = params.getlist("type")
    try:
        return StreamQuery.model_validate(data)
    except ValidationError as exc:
        error = exc.errors()[0]
        field = ".".join(str(p) for p in error["loc"]) or "query"
        if field == "since" and error["type"] == "greater_than_equal":
            raise InvalidValue("since must be >= 0", field=field) from None  # (as before)
        raise InvalidValue(f"query field {field!r}: {error['msg']} "
                           f"(got {str(error.get('input'))[:40]!r})", field=field) from None


__all__ = ["EventOut", "EventsPage", "GapOut", "ResetOut", "StreamQuery", "stream_query"]
