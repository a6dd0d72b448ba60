"""``GET /favicon.ico``: the service's icon (a small SVG: a rotary buffer's ring and a pointer),
so browser tabs on ``/docs``, ``/redoc`` and ``/dashboard`` show motionsim, not a 404."""

from __future__ import annotations

from fastapi import APIRouter
from fastapi.responses import Response

from ..decoded_json import DecodedJsonRoute

router = APIRouter(tags=["service"], route_class=DecodedJsonRoute)

FAVICON_URL = "/favicon.ico"

_SVG = (
    '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 32 32">'
    '<rect width="32" height="32" rx="6" fill="#123"/>'
    '<circle cx="16" cy="16" r="10" fill="none" stroke="#9cf" stroke-width="4"/>'
    '<path d="M16 16 L24 8" stroke="#fc6" stroke-width="3" stroke-linecap="round"/>'
    "</svg>"
)


@router.get(FAVICON_URL, include_in_schema=False)
async def favicon() -> Response:
    """The icon as SVG (browsers accept an SVG body at ``/favicon.ico``)."""
    return Response(_SVG, media_type="image/svg+xml",
                    headers={"cache-control": "public, max-age=86400"})


__all__ = ["FAVICON_URL", "router"]
