"""``/controllers/{id}/coord/{cs}``: PMAC coordinate systems and their rotary buffers.

Every mutation runs through ``handle.apply`` at the current simulated instant and never moves
the clock. A route used on a controller that is not a PMAC answers 404 ``not_found``.
"""

from __future__ import annotations

from typing import Annotated, Any

from fastapi import APIRouter, Path, Response

from ...app.registry import ControllerHandle
from ...sim.errors import NotFound
from ...sim.pmac import PmacController
from ..decoded_json import DecodedJsonRoute
from ..deps import HandleDep
from ..line_slices import precompile
from ..schemas.coord import CoordPublic, LinesAccepted, LinesIn, RotaryIn, RotaryPublic

router = APIRouter(tags=["coord"], route_class=DecodedJsonRoute)

CS = Annotated[int, Path(description="coordinate system number, 1..16 (404 otherwise)",
                         json_schema_extra={"minimum": 1, "maximum": 16})]
BASE = "/controllers/{controller_id}/coord/{cs}"


def _pmac(handle: ControllerHandle) -> PmacController:
    ctl = handle.controller
    if not isinstance(ctl, PmacController):
        raise NotFound(f"controller {handle.id!r} is a {handle.kind}, it has no coordinate systems")
    return ctl


def _coord(ctl: PmacController, cs: int) -> dict[str, Any]:
    """``ctl.coord(cs)`` with the CS's actual ``%`` feedrate override (what ``%`` reports)."""
    out = ctl.coord(cs)
    out["program"]["feed_override"] = ctl.coord_system(cs).feed_override
    return out


@router.get(BASE, response_model=CoordPublic)
def get_coord(handle: HandleDep, cs: CS) -> dict[str, Any]:
    return handle.apply(_coord, _pmac(handle), cs)


@router.put(BASE + "/rotary", response_model=RotaryPublic)
def put_rotary(handle: HandleDep, cs: CS, body: RotaryIn) -> dict[str, Any]:
    """``&cs DEFINE ROT size_words`` (409 ``conflict`` + ERR003 out of order).

    The REST resource counts as entering the new buffer with ``OPEN ROT`` (API.md): BREQ is
    evaluated at once, so an empty buffer below I17 lines ahead raises it."""
    return handle.apply(_pmac(handle).define_rotary, cs, body.size_words, entered=True)


@router.delete(BASE + "/rotary", status_code=204)
def delete_rotary(handle: HandleDep, cs: CS) -> Response:
    """``&cs DELETE ROT``."""
    handle.apply(_pmac(handle).delete_rotary, cs)
    return Response(status_code=204)


@router.post(BASE + "/rotary/lines", response_model=LinesAccepted)
async def post_lines(handle: HandleDep, cs: CS, body: LinesIn) -> dict[str, Any]:
    """Store a batch atomically (409 ``buffer_full`` / 422 ``parse_error``, nothing stored);
    at most ``MAX_BATCH_LINES`` lines, parsed in slices that let other clients be served."""
    ctl = _pmac(handle)
    compiled = await precompile(body.lines)
    result = handle.apply(ctl.load_lines, cs, body.lines, body.first_seq, compiled)
    return result._asdict()


@router.post(BASE + "/run", response_model=CoordPublic)
def post_run(handle: HandleDep, cs: CS) -> dict[str, Any]:
    """``B0 R`` (409 ``conflict`` + ERR015 without a rotary buffer)."""
    ctl = _pmac(handle)
    handle.apply(ctl.run, cs)
    return _coord(ctl, cs)


@router.post(BASE + "/quit", response_model=CoordPublic)
def post_quit(handle: HandleDep, cs: CS) -> dict[str, Any]:
    """``Q``: stop after the moves already calculated."""
    ctl = _pmac(handle)
    handle.apply(ctl.quit, cs)
    return _coord(ctl, cs)


@router.post(BASE + "/abort", response_model=CoordPublic)
def post_abort(handle: HandleDep, cs: CS) -> dict[str, Any]:
    """``A``: decelerate now; lookahead and queued synchronous M writes are discarded."""
    ctl = _pmac(handle)
    handle.apply(ctl.abort, cs)
    return _coord(ctl, cs)
