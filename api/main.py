"""The FastAPI application: ``create_app(settings)``.

Builds the registry of controllers from the settings, includes every router found in
``api/routes/`` (each module defining ``router``), installs the error handlers, and starts /
stops the realtime clocks in the lifespan. No module-level app: ``uvicorn --factory
api.main:create_app`` or ``motionsim serve``.
"""

from __future__ import annotations

import asyncio
import importlib
import pkgutil
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager

from fastapi import APIRouter, FastAPI
from fastapi.middleware.cors import CORSMiddleware
from fastapi_offline import FastAPIOffline

from ..app import __version__
from ..app.fatal import install_loop_handler
from ..app.registry import Registry
from ..app.service import build_registry
from ..app.settings import Settings
from . import openapi_extras
from . import routes as route_modules
from .body_guard import BodyGuard
from .errors import install_error_handlers
from .routes.favicon import FAVICON_URL
from .schemas.common import ERROR_RESPONSES
from .web_guard import WebGuard, allowed_host_set

#: Where the Swagger UI / ReDoc scripts and styles are served from.
DOCS_STATIC_URL = "/static/docs"


def discover_routers() -> list[tuple[str, APIRouter]]:
    """``(module name, router)`` of every ``motionsim.api.routes`` module with a ``router``."""
    found: list[tuple[str, APIRouter]] = []
    for info in sorted(pkgutil.iter_modules(route_modules.__path__), key=lambda i: i.name):
        if info.name.startswith("_"):
            continue
        module = importlib.import_module(f"{route_modules.__name__}.{info.name}")
        router = getattr(module, "router", None)
        if isinstance(router, APIRouter):
            found.append((info.name, router))
    return found


#: The top of ``/docs``: where to look first (issue 36 item 5: it linked neither).
DOCS_DESCRIPTION = (
    "The live view of every controller is the [dashboard](/dashboard). The contract these "
    "routes keep — fields, limits, error codes, the event types — is `docs/API.md`, shipped "
    "with the package's sources; `GET /` lists the controllers. Start with *controllers* and "
    "*clock*: make a controller (virtual clock), send it lines or commands, advance its clock, "
    "read its events."
)

#: The order ``/docs`` shows the route groups in: what every session needs first, then the
#: PMAC resources, then the Trio ones.
OPENAPI_TAGS = [
    {"name": "service", "description": "Health, the service's own settings and limits."},
    {"name": "controllers", "description": "Create, list, reset and delete controllers."},
    {"name": "clock", "description": "Virtual, realtime and host-paced time: advance, "
                                     "run-until, holders."},
    {"name": "events", "description": "The event log: pages, CSV, the WebSocket stream."},
    {"name": "terminal", "description": "The controller's own command line."},
    {"name": "variables", "description": "I/P/Q/M variables (PMAC), VR/TABLE (Trio)."},
    {"name": "coord", "description": "PMAC coordinate systems: rotary buffers, run, stop."},
    {"name": "plcs", "description": "PMAC PLC programs."},
    {"name": "recordings", "description": "What the card recorded: PMAC data gathering, "
                                          "Trio SCOPE (JSON columns or CSV)."},
    {"name": "faults", "description": "Injected faults for testing a host's retry logic."},
    {"name": "trio programs", "description": "Trio BASIC programs: store, list, run."},
    {"name": "trio processes", "description": "Trio processes and their state."},
    {"name": "trio axes", "description": "Trio axes, their buffers and moves."},
]


def create_app(settings: Settings | None = None, registry: Registry | None = None) -> FastAPI:
    """The service for ``settings`` (defaults if ``None``); ``registry`` overrides the one built.

    ``motionsim.app.state``: ``settings``, ``registry``, ``ready`` (``/health`` answers 200 when
    True; ``motionsim serve`` sets it once every protocol listener accepts), ``listeners``.
    """
    settings = settings if settings is not None else Settings()
    registry = registry if registry is not None else build_registry(settings)

    @asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        install_loop_handler(asyncio.get_running_loop())
        await registry.start()
        try:
            yield
        finally:
            for server in list(app.state.listeners):
                server.close()
            await registry.close()

    # /docs and /redoc with Swagger UI and ReDoc served from the fastapi-offline package (no CDN:
    # they work in CI, in a container and offline).
    app = FastAPIOffline(
        title="motionsim",
        version=__version__,
        summary="Discrete-event simulation of Turbo PMAC and Trio Motion Coordinator "
                "program buffering",
        description=DOCS_DESCRIPTION,
        openapi_tags=OPENAPI_TAGS,
        lifespan=lifespan,
        responses=ERROR_RESPONSES,
        static_url=DOCS_STATIC_URL,
        favicon_url=FAVICON_URL,
    )
    app.state.settings = settings
    app.state.registry = registry
    app.state.ready = True
    app.state.listeners = []
    install_error_handlers(app)
    for _, router in discover_routers():
        app.include_router(router)
    install_guards(app, settings)
    openapi_extras.install(app)
    return app


def install_guards(app: FastAPI, settings: Settings) -> None:
    """Request bodies checked (api/body_guard.py), then Host / Origin / token (api/web_guard.py);
    CORS only for the origins ``settings.cors_origins`` names (off by default)."""
    app.add_middleware(BodyGuard, max_body_bytes=settings.max_body_bytes,
                       routes=app.router.routes)
    app.add_middleware(WebGuard, allowed_hosts=allowed_host_set(settings.host,
                                                                settings.allowed_hosts),
                       token=settings.token, cors_origins=settings.cors_origins)
    if settings.cors_origins:
        app.add_middleware(CORSMiddleware, allow_origins=settings.cors_origins,
                           allow_methods=["*"], allow_headers=["*"],
                           allow_credentials=False)


__all__ = ["DOCS_STATIC_URL", "create_app", "discover_routers"]
