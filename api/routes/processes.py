"""``/controllers/{id}/processes``: the Trio BASIC processes and their states."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Path

from ..decoded_json import DecodedJsonRoute
from ..deps import HandleDep
from ..schemas.processes import ProcessOut
from .axes import trio_of

router = APIRouter(tags=["trio processes"], route_class=DecodedJsonRoute)


@router.get("/controllers/{controller_id}/processes", response_model=list[ProcessOut])
def list_processes(handle: HandleDep) -> list[dict]:
    """Every process that has run a program: running, blocked (at a move line) or stopped."""
    return handle.apply(trio_of(handle).processes)


@router.post("/controllers/{controller_id}/processes/{process}/stop", response_model=ProcessOut)
def stop_process(
    handle: HandleDep,
    process: Annotated[int, Path(ge=1, le=32, description="process number, 1..the "
                                                          "controller's (at most 32)")],
) -> dict:
    return handle.apply(trio_of(handle).stop_process, process)
