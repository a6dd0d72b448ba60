"""Route dependencies as named types.

``HandleDep`` resolves the ``{controller_id}`` path parameter to the running
:class:`motionsim.app.registry.ControllerHandle` (404 ``not_found`` if there is none);
``RegistryDep`` is the service's :class:`motionsim.app.registry.Registry` (kept on
``motionsim.app.state.registry``).

A route::

    @router.get("/controllers/{controller_id}/coord/{cs}")
    def get_coord(handle: HandleDep, cs: int) -> CoordOut:
        return handle.controller.coord(cs)
"""

from __future__ import annotations

from typing import Annotated

from fastapi import Depends, Path, Request
from starlette.requests import HTTPConnection

from ..app.registry import ControllerHandle, Registry
from ..app.settings import Settings


async def get_registry(conn: HTTPConnection) -> Registry:
    """The registry of the app serving this request (or WebSocket)."""
    return conn.app.state.registry


async def get_settings(request: Request) -> Settings:
    return request.app.state.settings


async def get_handle(
    registry: Annotated[Registry, Depends(get_registry)],
    controller_id: Annotated[str, Path(description="the controller's id, e.g. `pmac`")],
) -> ControllerHandle:
    """The handle of ``{controller_id}``; raises ``NotFound`` (404).

    Resolved on the event loop (an ``async`` dependency), it binds the handle to that loop, so a
    plain ``def`` route — which FastAPI runs in a worker thread — still applies its mutations
    on the loop through ``handle.apply``.
    """
    handle = registry.get(controller_id)
    handle.ensure_running()
    return handle


RegistryDep = Annotated[Registry, Depends(get_registry)]
HandleDep = Annotated[ControllerHandle, Depends(get_handle)]
ControllerDep = HandleDep  # the name STYLE.md uses
SettingsDep = Annotated[Settings, Depends(get_settings)]

__all__ = ["ControllerDep", "HandleDep", "RegistryDep", "SettingsDep", "get_handle",
           "get_registry", "get_settings"]
