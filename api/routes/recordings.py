"""``/controllers/{id}/gather`` (Turbo PMAC data gathering) and ``/controllers/{id}/scope``
(Trio SCOPE): what the controller recorded, as JSON columns or CSV.

Paged like the event log: ``since`` (samples to skip, 0 = the oldest held) and ``limit``
(default 1000, at most 100 000); the page's ``next`` is the ``since`` of the next one. With
``Accept: text/csv`` the same page is CSV: a header ``cycle,t,<source>...`` and one row per
sample. A PMAC asked for ``/scope`` or a Trio for ``/gather`` is 404 ``not_found`` naming
the resource it has. The samples are read at the current simulated instant (the clock is
brought to it first, as for the event log).
"""

from __future__ import annotations

import csv
import io
from typing import Annotated, Any

from fastapi import APIRouter, Header, Query, Response

from ...sim.errors import NotFound
from ...sim.recording import Recording
from ..decoded_json import DecodedJsonRoute
from ..deps import HandleDep
from ..schemas.recordings import RecordingPage

router = APIRouter(tags=["recordings"], route_class=DecodedJsonRoute)

#: Which controller kind has which recording resource.
RESOURCE = {"gather": "pmac", "scope": "trio"}

SinceQuery = Annotated[int, Query(ge=0, le=2**63 - 1,
                                  description="samples to skip (0: from the oldest held)")]
LimitQuery = Annotated[int, Query(ge=1, le=100_000, description="samples in the page")]
AcceptHeader = Annotated[str | None, Header(description="`text/csv` for CSV")]


def _recording(handle: Any, resource: str) -> Recording:
    kind = handle.controller.kind
    if RESOURCE[resource] != kind:
        other = next(r for r, k in RESOURCE.items() if k == kind)
        raise NotFound(f"a {kind} controller records with /controllers/{handle.id}/{other}, "
                       f"not /{resource}", field="resource")
    handle.clock.sync()
    rec: Recording = handle.controller.recording()
    return rec


def _page(rec: Recording, since: int, limit: int, accept: str | None) -> Any:
    end = min(len(rec.cycles), since + limit)
    cycles = list(rec.cycles[since:end])
    times = rec.times()[since:end]
    columns = [list(col[since:end]) for col in rec.columns]
    if accept is not None and "text/csv" in accept:
        out = io.StringIO()
        writer = csv.writer(out, lineterminator="\n")
        writer.writerow(["cycle", "t", *rec.names])
        for j, k in enumerate(cycles):
            writer.writerow([k, repr(times[j]), *(repr(col[j]) for col in columns)])
        return Response(out.getvalue(), media_type="text/csv")
    body: dict[str, Any] = {
        "kind": rec.kind, "running": rec.running, "wrapped": rec.wrapped,
        "capacity": rec.capacity, "period_cycles": rec.period_cycles,
        "servo_period_s": rec.servo_period_s, "total": len(rec.cycles), "since": since,
        "next": max(since, end), "sources": list(rec.sources),
        "columns": {"cycle": cycles, "t": times,
                    **{name: col for name, col in zip(rec.names, columns, strict=True)}},
    }
    return body


_RESPONSES: dict[int | str, dict[str, Any]] = {
    200: {"content": {"text/csv": {"schema": {"type": "string"}}},
          "description": "JSON columns, or CSV with `Accept: text/csv`"}}


@router.get("/controllers/{controller_id}/gather", response_model=RecordingPage,
            responses=_RESPONSES)
async def get_gather(handle: HandleDep, since: SinceQuery = 0, limit: LimitQuery = 1000,
                     accept: AcceptHeader = None) -> Any:
    """A Turbo PMAC's data gathering (`DEFINE GATHER`, `GATHER`; docs/pmac.md)."""
    return _page(_recording(handle, "gather"), since, limit, accept)


@router.get("/controllers/{controller_id}/scope", response_model=RecordingPage,
            responses=_RESPONSES)
async def get_scope(handle: HandleDep, since: SinceQuery = 0, limit: LimitQuery = 1000,
                    accept: AcceptHeader = None) -> Any:
    """A Trio's SCOPE capture in TABLE (`SCOPE(ON, ...)`, `TRIGGER`; docs/trio.md)."""
    return _page(_recording(handle, "scope"), since, limit, accept)
