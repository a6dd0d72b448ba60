"""``/controllers/{id}/terminal``: the controller's own command line (the REST host port).

``&n`` / ``#n`` addressing and an open buffer persist between POSTs (the REST terminal is one
port). Timing per API.md: see :meth:`app.registry.ControllerHandle.command`.
"""

from __future__ import annotations

from fastapi import APIRouter
from motionsim.api.deps import HandleDep
from motionsim.api.schemas.terminal import TerminalIn, TerminalOut, TerminalState

router = APIRouter(tags=["terminal"])


@router.post("/controllers/{controller_id}/terminal", response_model=TerminalOut)
async def post_terminal(body: TerminalIn, handle: HandleDep) -> dict:
    reply = await handle.command(body.command)
    if not reply.done:
        return {"reply": "", "error": None, "pending": True}
    return {"reply": reply.reply, "error": reply.error, "pending": False}


@router.get("/controllers/{controller_id}/terminal", response_model=TerminalState)
async def get_terminal(handle: HandleDep) -> dict:
    """Whether the command line is locked (Trio: a move waiting for a buffer) and what waits."""
    state = getattr(handle.controller, "terminal_state", None)
    if state is None:
        return {"locked": False, "pending": []}
    return handle.apply(state)
