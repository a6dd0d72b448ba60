"""``GET /health``: 200 once every listener accepts connections; ``GET /``: what this is."""

from __future__ import annotations

from fastapi import APIRouter, Request
from fastapi.responses import JSONResponse

from ...app import __version__
from ..decoded_json import DecodedJsonRoute
from ..schemas.common import Health, ServiceInfo

router = APIRouter(tags=["service"], route_class=DecodedJsonRoute)


@router.get("/health", response_model=Health,
            responses={503: {"model": Health, "description": "still starting"}})
async def health(request: Request) -> JSONResponse | Health:
    if not request.app.state.ready:
        return JSONResponse({"status": "starting"}, status_code=503)
    return Health(status="ok")


@router.get("/", response_model=ServiceInfo)
async def root(request: Request) -> ServiceInfo:
    """What this service is and where to look next."""
    return ServiceInfo(service="motionsim", version=__version__, docs="/docs", redoc="/redoc",
                       openapi="/openapi.json", dashboard="/dashboard",
                       controllers=request.app.state.registry.ids())
