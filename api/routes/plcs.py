"""``/controllers/{id}/plcs``: the PMAC's PLC programs (TSRM p39, p381; TUM p236-237).

``GET /plcs`` lists each PLC with a program (state, scans, last scan time) and I5, and in
``compiled_plcs`` the compiled PLCs (``OPEN PLCC n``) the same way;
``GET|PUT /plcs/{n}`` reads / replaces one program whole (422 ``parse_error`` with ``line``
and ``column``, nothing changed); ``POST /plcs/{n}/enable|disable`` are ``ENABLE PLC n`` /
``DISABLE PLC n``. Everything acts at the current simulated instant and never moves the clock.
The terminal commands (``OPEN PLC n``, ``CLEAR``, ``CLOSE``, ``ENABLE PLC``...) do the same
through the host port.
"""

from __future__ import annotations

from typing import Annotated, Any

from fastapi import APIRouter, Path

from ...app.registry import ControllerHandle
from ...sim.errors import Halted, NotFound
from ...sim.pmac import PlcProgram, compile_plc, stored_entries
from ..decoded_json import DecodedJsonRoute
from ..deps import HandleDep
from ..off_loop import off_loop
from ..schemas.plcs import PlcDetail, PlcList, PlcProgramIn

router = APIRouter(tags=["plcs"], route_class=DecodedJsonRoute)

BASE = "/controllers/{controller_id}/plcs"
N = Annotated[int, Path(description="PLC number 0..31 (404 otherwise)",
                        json_schema_extra={"minimum": 0, "maximum": 31})]


def _plcs(handle: ControllerHandle) -> Any:
    plcs = getattr(handle.controller, "plcs", None)
    if plcs is None:
        raise NotFound(f"controller {handle.id!r} is a {handle.kind}, it has no PLC programs")
    return plcs


def _running(handle: ControllerHandle) -> None:
    if handle.controller.halted:
        raise Halted("the watchdog has tripped: the controller answers nothing until reset")


@router.get(BASE, response_model=PlcList)
async def list_plcs(handle: HandleDep) -> dict[str, Any]:
    plcs = _plcs(handle)

    def read() -> dict[str, Any]:
        return {"i5": plcs.i5(), "plcs": plcs.to_list(),
                "compiled_plcs": plcs.to_list(compiled=True)}

    return handle.apply(read)


@router.get(BASE + "/{n}", response_model=PlcDetail)
async def get_plc(handle: HandleDep, n: N) -> dict[str, Any]:
    return handle.apply(_plcs(handle).describe, n)


def _compile(text: str) -> PlcProgram:
    """``compile_plc``, and the program's listing worked out (``LIST PLC`` reads it)."""
    program = compile_plc(text)
    stored_entries(program.lines, plc=True)
    return program


@router.put(BASE + "/{n}", response_model=PlcDetail)
async def put_plc(handle: HandleDep, n: N, body: PlcProgramIn) -> dict[str, Any]:
    """Replace PLC ``n``'s program (like OPEN PLC n CLEAR ... CLOSE, all or nothing)."""
    plcs = _plcs(handle)
    program = await off_loop(_compile, body.text)  # seconds for a large PLC: off the loop

    def load() -> dict[str, Any]:
        _running(handle)
        plcs.load(n, body.text, program)
        return plcs.describe(n)

    return handle.apply(load)


def _set(handle: ControllerHandle, n: int, enable: bool) -> dict[str, Any]:
    plcs = _plcs(handle)

    def act() -> dict[str, Any]:
        _running(handle)
        plcs.plc(n)  # 404 for a bad number
        plcs.set_enabled((n,), enable)
        return plcs.describe(n)

    return handle.apply(act)


@router.post(BASE + "/{n}/enable", response_model=PlcDetail)
async def enable_plc(handle: HandleDep, n: N) -> dict[str, Any]:
    return _set(handle, n, True)


@router.post(BASE + "/{n}/disable", response_model=PlcDetail)
async def disable_plc(handle: HandleDep, n: N) -> dict[str, Any]:
    return _set(handle, n, False)
