"""A controller's recording on the wire (``GET /controllers/{id}/gather`` / ``.../scope``)."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field


class RecordingSource(BaseModel):
    """One recorded source: PMAC ``I50nn`` (its modified address, what it reads, its width),
    Trio a SCOPE parameter (the first TABLE entry of its range)."""

    model_config = ConfigDict(extra="forbid")

    name: str = Field(description="the column name: `I5001` (PMAC), `MPOS AXIS(5)` (Trio)")
    spec: str | None = Field(None, description="PMAC: the I50nn value, e.g. `$800088`")
    address: str | None = Field(None, description="PMAC: what it reads, e.g. `D:$000088`")
    bits: int | None = Field(None, description="PMAC: 24 or 48")
    table_start: int | None = Field(None, description="Trio: TABLE index of its first sample")


class RecordingPage(BaseModel):
    """Samples ``since`` .. ``next - 1`` of the recording, oldest first, as columns: ``cycle``
    (the servo cycle of each sample), ``t`` (its simulated instant, ``cycle ×
    servo_period_s`` exactly) and one column per source. Pass ``next`` as ``since`` to go on."""

    model_config = ConfigDict(json_schema_extra={"examples": [{
        "kind": "gather", "running": False, "wrapped": False, "capacity": 1000,
        "period_cycles": 1, "servo_period_s": 0.000442708, "total": 2, "since": 0, "next": 2,
        "sources": [{"name": "I5001", "spec": "$800088", "address": "D:$000088", "bits": 48}],
        "columns": {"cycle": [8, 9], "t": [0.003541666, 0.003984375],
                    "I5001": [0.0, 3072.0]}}]})

    kind: str = Field(description="`gather` (PMAC data gathering) or `scope` (Trio SCOPE)")
    running: bool = Field(description="still recording")
    wrapped: bool = Field(description="the buffer went round: the oldest samples are gone")
    capacity: int = Field(description="samples the buffer holds")
    period_cycles: int = Field(description="servo cycles between samples (0: single shot)")
    servo_period_s: float
    total: int = Field(description="samples held now")
    since: int
    next: int
    sources: list[RecordingSource]
    columns: dict[str, list[int] | list[float]] = Field(
        description="`cycle` (int), `t` (s), then one column per source")
