"""``GET /health``: 200 once every listener accepts connections."""

from __future__ import annotations

from fastapi import APIRouter, Request
from fastapi.responses import JSONResponse

from api.schemas.common import Health

router = APIRouter(tags=["service"])


@router.get("/health", response_model=Health,
            responses={503: {"model": Health, "description": "still starting"}})
def health(request: Request) -> JSONResponse | Health:
    if not request.app.state.ready:
        return JSONResponse({"status": "starting"}, status_code=503)
    return Health(status="ok")
