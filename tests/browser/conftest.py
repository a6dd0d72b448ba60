"""A served motionsim (``motionsim serve`` subprocess on a free 127.0.0.1 port) and the dashboard
open in headless Chromium — Debian's ``chromium`` package driven by Playwright for Python
(``executable_path``; Playwright downloads no browser).

The tests skip only when no Chromium is installed, saying so; under CI (``CI`` set) a missing
Chromium is a failure, since ``.ci/run`` installs it. Every events WebSocket of the page goes
through a Playwright route that forwards it to the service unchanged, so a test can close a
connection's server side (:attr:`Browser.sockets`).
"""

from __future__ import annotations

import os
import re
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any

import pytest
from motionsim.app.client import MotionSimClient

from tests.browser.served import CHROMIUM_ARGS, chromium_path, serve


@pytest.fixture(scope="module")
def served() -> Iterator[str]:
    """``motionsim serve`` on a free port (virtual clocks, no protocol listeners); its URL."""
    with serve() as url:
        yield url


@dataclass
class Browser:
    """The dashboard page and what it did: console errors and its event sockets."""

    page: Any
    url: str
    errors: list[str] = field(default_factory=list)
    sockets: list[tuple[str, Any, Any]] = field(default_factory=list)  # (url, page side, server)

    def live_sockets(self, controller: str) -> list[tuple[Any, Any]]:
        path = f"/controllers/{controller}/events"
        return [(ws, server) for url, ws, server in self.sockets if path in url]


@contextmanager
def dashboard(url: str, path: str = "/dashboard", route_sockets: bool = True) -> Iterator[Browser]:
    """Chromium with ``url + path`` open; skips (fails under CI) without a Chromium.

    With ``route_sockets`` every events WebSocket goes through a Playwright route (so a test
    can close its server side); Playwright's sync API forwards routed messages only while
    the test calls into it, so a test that keeps the service busy between calls opens the
    page without."""
    exe = chromium_path()
    if exe is None:
        reason = ("no Chromium installed (apt-get install chromium; or set MOTIONSIM_CHROMIUM): "
                  "the dashboard's browser tests cannot run")
        if os.environ.get("CI"):
            pytest.fail(f"{reason} — .ci/run must install it")
        print(f"SKIP: {reason}", file=sys.stderr)
        pytest.skip(reason)
    from playwright.sync_api import sync_playwright

    with sync_playwright() as pw:
        chromium = pw.chromium.launch(executable_path=exe, headless=True, args=CHROMIUM_ARGS)
        context = chromium.new_context(viewport={"width": 1500, "height": 1000})
        page = context.new_page()
        b = Browser(page=page, url=url)
        page.on("pageerror", lambda exc: b.errors.append(f"pageerror: {exc}"))

        def console(m: Any) -> None:
            # a REST call the page makes may meet a controller another client just deleted
            # (404): the browser logs that as "Failed to load resource"; the page's own files
            # are checked by status below
            if m.type == "error" and not m.text.startswith("Failed to load resource"):
                b.errors.append(f"console: {m.text}")

        def response(r: Any) -> None:
            if "/dashboard" in r.url and r.status != 200:
                b.errors.append(f"{r.status} {r.url}")

        page.on("console", console)
        page.on("response", response)

        def forward(ws: Any) -> None:
            b.sockets.append((ws.url, ws, ws.connect_to_server()))

        if route_sockets:
            page.route_web_socket(re.compile(r".*/controllers/.*/events.*"), forward)
        page.set_default_timeout(15_000)
        page.goto(f"{url}{path}")
        try:
            yield b
        finally:
            context.close()
            chromium.close()


@pytest.fixture(scope="module")
def browser(served: str) -> Iterator[Browser]:
    with dashboard(served) as b:
        yield b


@pytest.fixture(scope="module")
def ms(served: str) -> Iterator[MotionSimClient]:
    with MotionSimClient(served) as client:
        yield client
