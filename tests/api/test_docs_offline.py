"""/docs and /redoc work without a network: the HTML pages and every script, style sheet and
icon they reference are served by motionsim itself (from the fastapi-offline package), so the
interactive docs load in CI, in a container or on a plane."""

from __future__ import annotations

from html.parser import HTMLParser
from urllib.parse import urljoin, urlsplit

import httpx
import pytest


class _References(HTMLParser):
    """Every ``src`` / ``href`` in a page and every URL string its inline scripts load."""

    def __init__(self) -> None:
        super().__init__()
        self.urls: list[str] = []
        self._in_script = False
        self.scripts: list[str] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        self._in_script = tag == "script"
        for name, value in attrs:
            if name in ("src", "href") and value:
                self.urls.append(value)

    def handle_endtag(self, tag: str) -> None:
        self._in_script = False

    def handle_data(self, data: str) -> None:
        if self._in_script:
            self.scripts.append(data)


def _page(base: str, path: str) -> tuple[httpx.Response, _References]:
    r = httpx.get(base + path, timeout=10)
    parser = _References()
    parser.feed(r.text)
    return r, parser


@pytest.mark.parametrize("path, needs", [
    ("/docs", {"swagger-ui-bundle.js", "swagger-ui.css"}),
    ("/redoc", {"redoc.standalone.js"}),
])
def test_docs_page_and_every_asset_it_references_come_from_the_server(motionsim, path, needs):
    base = motionsim.url
    r, refs = _page(base, path)
    assert r.status_code == 200 and "text/html" in r.headers["content-type"]
    assert refs.urls, "the page references no asset"
    names = {urlsplit(u).path.rsplit("/", 1)[-1] for u in refs.urls}
    assert needs <= names
    for url in refs.urls:
        full = urljoin(base + path, url)
        assert full.startswith(base + "/"), f"{path} loads {url} from elsewhere"
        asset = httpx.get(full, timeout=10)
        assert asset.status_code == 200, url
        assert len(asset.content) > 100, url
    # nothing in the page's inline script points off the server (no CDN, no web fonts)
    for script in refs.scripts:
        assert "http://" not in script and "https://" not in script
    assert "fonts.googleapis" not in r.text


def test_docs_scripts_are_real_swagger_ui_and_redoc_bundles(motionsim):
    _, docs = _page(motionsim.url, "/docs")
    _, redoc = _page(motionsim.url, "/redoc")
    js = {u for u in docs.urls + redoc.urls if u.endswith(".js")}
    bodies = {u.rsplit("/", 1)[-1]: httpx.get(urljoin(motionsim.url, u), timeout=10)
              for u in js}
    assert "SwaggerUIBundle" in bodies["swagger-ui-bundle.js"].text
    assert "javascript" in bodies["swagger-ui-bundle.js"].headers["content-type"]
    assert "Redoc" in bodies["redoc.standalone.js"].text
    # the page loads the spec from the same server
    assert "/openapi.json" in "".join(docs.scripts)
    assert httpx.get(motionsim.url + "/openapi.json", timeout=10).json()["info"]["title"] \
        == "motionsim"


def test_the_service_has_a_favicon(motionsim):
    r = httpx.get(motionsim.url + "/favicon.ico", timeout=10)
    assert r.status_code == 200
    assert r.headers["content-type"].startswith("image/svg+xml")
    assert r.text.startswith("<svg")


def test_root_lists_docs_redoc_dashboard_and_openapi(motionsim):
    body = httpx.get(motionsim.url + "/", timeout=10).json()
    assert body["docs"] == "/docs" and body["redoc"] == "/redoc"
    assert body["dashboard"] == "/dashboard" and body["openapi"] == "/openapi.json"
    for key in ("docs", "redoc", "dashboard", "openapi"):
        assert httpx.get(motionsim.url + body[key], timeout=10).status_code == 200, key
