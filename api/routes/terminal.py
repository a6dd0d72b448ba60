"""``/controllers/{id}/terminal``: the controller's own command line (the REST host port).

``&n`` / ``#n`` addressing and an open buffer persist between POSTs (the REST terminal is one
port). Timing per API.md: see :meth:`app.registry.ControllerHandle.command`.
"""

from __future__ import annotations

from fastapi import APIRouter

from ...sim.pmac import meaning
from ..decoded_json import DecodedJsonRoute
from ..deps import HandleDep
from ..schemas.terminal import TerminalIn, TerminalOut, TerminalState

router = APIRouter(tags=["terminal"], route_class=DecodedJsonRoute)


@router.post(
    "/controllers/{controller_id}/terminal",
    response_model=TerminalOut,
    response_model_exclude_unset=True,
)
async def post_terminal(body: TerminalIn, handle: HandleDep) -> dict:
    reply = await handle.command(body.command)
    unread = getattr(handle.controller, "unread_output", None)
    output = handle.apply(unread, "rest") if unread is not None else []
    if not reply.done or reply.answered_pending:
        out: dict = {"reply": "", "error": None, "pending": True}
    else:
        out = {"reply": reply.reply, "error": reply.error, "pending": False}
    # an error explained for people; success stays 3 fields
    if out["pending"] is False and reply.error is not None:
        detail = getattr(reply, "detail", None)
        out["error_meaning"] = meaning(reply.error)
        out["not_simulated"] = detail is not None and detail[0] == "not_simulated"
        out["detail"] = detail[1] if detail is not None else None
    if output:  # Trio channel-0 output / PMAC SEND lines since the previous command
        out["output"] = output
    return out


@router.get("/controllers/{controller_id}/terminal", response_model=TerminalState)
async def get_terminal(handle: HandleDep) -> dict:
    """Whether the command line is locked (Trio: a move waiting for a buffer) and what waits."""
    state = getattr(handle.controller, "terminal_state", None)
    if state is None:
        return {"locked": False, "pending": []}
    return handle.apply(state)
