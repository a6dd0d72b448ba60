"""``/controllers/{id}/programs/{name}``: Trio BASIC programs, stored as text, run in processes.

``PUT`` takes the program as ``text/plain``; it is parsed and compiled first — a syntax or
structure error is 422 ``parse_error`` with ``line`` and ``column`` and the stored program (if
any) stays as it was.
"""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Path, Request, Response
from fastapi.responses import PlainTextResponse

from ...sim.errors import InvalidValue
from ..decoded_json import DecodedJsonRoute
from ..deps import HandleDep
from ..off_loop import off_loop
from ..schemas.programs import ProgramList, ProgramStored, RunIn, RunOut
from .axes import trio_of

router = APIRouter(tags=["trio programs"], route_class=DecodedJsonRoute)

NameParam = Annotated[str, Path(min_length=1, max_length=32, pattern=r"^[A-Za-z_][A-Za-z0-9_]*$",
                                description="program name: a letter or _, then letters, "
                                            "digits, _ (up to 32)")]
MAX_PROGRAM_BYTES = 1_000_000

_TEXT_BODY = {
    "requestBody": {
        "required": True,
        "content": {"text/plain": {"schema": {"type": "string", "maxLength": 1_000_000},
                                   "example": "MOVE(10) AXIS(0)\n"}},
    }
}


@router.get("/controllers/{controller_id}/programs", response_model=ProgramList)
def list_programs(handle: HandleDep) -> dict:
    return {"programs": handle.apply(trio_of(handle).program_names)}




@router.put(
    "/controllers/{controller_id}/programs/{name}",
    response_model=ProgramStored,
    status_code=201,
    openapi_extra=_TEXT_BODY,
)
async def put_program(handle: HandleDep, name: NameParam, request: Request) -> dict:
    raw = await request.body()
    if len(raw) > MAX_PROGRAM_BYTES:
        raise InvalidValue(f"program text over {MAX_PROGRAM_BYTES} bytes", field="body")
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise InvalidValue(f"program text is not UTF-8 (byte {exc.start})", field="body") from None
    ctrl = trio_of(handle)
    # compiling a large text takes a while: off the loop, against a snapshot of what it reads
    compiler = handle.apply(ctrl.detached_compiler, name) if text.strip() else None
    pre = await off_loop(compiler, text) if compiler is not None else None
    handle.apply(ctrl.store_program, name, text, pre)
    return {"name": name.upper(), "lines": len(text.splitlines())}


@router.get(
    "/controllers/{controller_id}/programs/{name}",
    # no response_class: its media type would also be claimed for the JSON error bodies
    responses={200: {"content": {"text/plain": {"schema": {"type": "string"}}}}},
)
def get_program(handle: HandleDep, name: NameParam) -> PlainTextResponse:
    return PlainTextResponse(handle.apply(trio_of(handle).program, name))


@router.delete("/controllers/{controller_id}/programs/{name}", status_code=204)
def delete_program(handle: HandleDep, name: NameParam) -> Response:
    handle.apply(trio_of(handle).delete_program, name)
    return Response(status_code=204)


@router.post("/controllers/{controller_id}/programs/{name}/run", response_model=RunOut)
def run_program(handle: HandleDep, name: NameParam, body: RunIn | None = None) -> dict:
    ctrl = trio_of(handle)
    process = body.process if body is not None else None
    return {"process": handle.apply(ctrl.run_program, name, process)}


