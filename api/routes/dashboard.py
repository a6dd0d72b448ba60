"""``GET /dashboard``: the live dashboard, static files shipped in the package.

The page (``api/static/dashboard/``: HTML, CSS, ES modules; no build step, nothing loaded from
elsewhere) uses only the public API: ``/controllers``, ``/clock``, ``/terminal``, PMAC
``/coord/{cs}`` and ``/variables``, Trio ``/axes`` and ``/processes``, and each controller's
events WebSocket with ``batch=true``. Not part of ``/openapi.json``.
"""

from __future__ import annotations

from pathlib import Path

from fastapi import APIRouter
from fastapi.responses import FileResponse

from ...sim.errors import NotFound
from ..decoded_json import DecodedJsonRoute

#: The dashboard's files (package data, see pyproject.toml).
STATIC_DIR = Path(__file__).resolve().parent.parent / "static" / "dashboard"

#: Content types by suffix (module scripts must be served as JavaScript).
_TYPES = {".html": "text/html", ".css": "text/css", ".js": "text/javascript",
          ".png": "image/png", ".svg": "image/svg+xml", ".txt": "text/plain"}

router = APIRouter(tags=["service"], route_class=DecodedJsonRoute)


@router.get("/dashboard", include_in_schema=False)
def dashboard() -> FileResponse:
    return _file(STATIC_DIR / "index.html")


@router.get("/dashboard/static/{path:path}", include_in_schema=False)
def dashboard_file(path: str) -> FileResponse:
    """A file of the dashboard; 404 for anything outside its folder."""
    target = (STATIC_DIR / path).resolve()
    if not target.is_relative_to(STATIC_DIR) or not target.is_file() \
            or target.suffix not in _TYPES:
        raise NotFound(f"no dashboard file {path!r}")
    return _file(target)


def _file(target: Path) -> FileResponse:
    return FileResponse(target, media_type=_TYPES[target.suffix],
                        headers={"cache-control": "no-cache"})
