"""``GET /dashboard``: the page and every file it loads come from the service itself.

Offline by construction: the HTML's scripts and styles, and each module's imports, are
followed to the end; all are served from ``/dashboard/static`` with the content type a
browser requires (module scripts must be JavaScript), and none names another host. The
browser tests (tests/browser) check what the page shows.
"""

from __future__ import annotations

import re

import pytest

pytestmark = pytest.mark.anyio

#: The one absolute URL allowed: the SVG namespace, an identifier that is never fetched.
SVG_NS = "http://www.w3.org/2000/svg"
REFS = re.compile(r'(?:src|href)="([^"]+)"|from\s+"([^"]+)"|import\s+"([^"]+)"')


def _resolve(base: str, ref: str) -> str:
    if ref.startswith("/"):
        return ref
    parts = base.rsplit("/", 1)[0].split("/")
    for piece in ref.split("/"):
        if piece == "..":
            parts.pop()
        elif piece != ".":
            parts.append(piece)
    return "/".join(parts)


async def test_dashboard_page_and_all_it_loads_are_served_here_and_offline(api):
    seen: dict[str, str] = {}
    todo = ["/dashboard"]
    while todo:
        path = todo.pop()
        if path in seen:
            continue
        r = await api.get(path)
        assert r.status_code == 200, path
        seen[path] = r.headers["content-type"]
        text = r.text
        assert "https://" not in text and "http://" not in text.replace(SVG_NS, ""), path
        for m in REFS.finditer(text):
            ref = next(g for g in m.groups() if g)
            if ref.startswith("data:") or ref == "/docs":
                continue
            todo.append(_resolve(path, ref))
    scripts = [p for p in seen if p.endswith(".js")]
    assert "/dashboard/static/js/main.js" in scripts and len(scripts) >= 5
    assert all(seen[p].startswith("text/javascript") for p in scripts)
    assert seen["/dashboard"].startswith("text/html")
    assert seen["/dashboard/static/dashboard.css"].startswith("text/css")
    main = (await api.get("/dashboard/static/js/stream.js")).text
    assert "batch" in main and "since" in main and "epoch" in main


@pytest.mark.parametrize("path", ["../routes/dashboard.py", "%2e%2e/%2e%2e/main.py",
                                  "js/nothing.js", "js"])
async def test_nothing_outside_the_dashboard_folder_is_served(api, path):
    r = await api.get(f"/dashboard/static/{path}")
    assert r.status_code == 404
    assert r.json()["code"] == "not_found"


async def test_dashboard_is_not_in_openapi(api):
    paths = (await api.get("/openapi.json")).json()["paths"]
    assert not [p for p in paths if p.startswith("/dashboard")]
