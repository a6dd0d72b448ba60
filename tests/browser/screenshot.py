"""``make screenshot``: the README's dashboard pictures, from a real run.

Serves motionsim, streams the rotary program and runs TN20-16 (scenario.py), types a few
commands at the page's terminals, and saves one picture of each controller's tab:
``docs/dashboard-pmac.png`` and ``docs/dashboard-trio.png``.

    .venv/bin/python -m tests.browser.screenshot [OUT_DIR]
"""

from __future__ import annotations

import sys
from pathlib import Path

from motionsim.app.client import MotionSimClient
from playwright.sync_api import Page, sync_playwright

from tests.browser.scenario import ROOT, run_tn20, stream_rotary
from tests.browser.served import CHROMIUM_ARGS, chromium_path, serve

VIEWPORT = {"width": 1440, "height": 760}


def _settle(page: Page, cid: str, ms: MotionSimClient) -> None:
    want = ms.events(cid, since=0, limit=100_000).next
    page.wait_for_function(
        """([cid, want]) => {
             const el = document.querySelector(`[data-controller="${cid}"] [data-role=stream]`);
             return el && el.isConnected && Number(el.dataset.lastSeq) >= want; }""",
        arg=[cid, want])
    page.wait_for_timeout(400)   # a few frames and one poll (I16/I17, DPOS, clock)


def _type(page: Page, cid: str, command: str) -> None:
    box = page.locator(f'[data-controller="{cid}"] [data-role=command]')
    box.fill(command)
    box.press("Enter")
    page.wait_for_function(
        """([cid, cmd]) => [...document.querySelectorAll(
             `[data-controller="${cid}"] .entry`)].some((e) => e.dataset.command === cmd
             && !e.querySelector('.pending'))""", arg=[cid, command])


def _tab(page: Page, cid: str) -> None:
    page.click(f'[data-tab="{cid}"] button.pick')
    page.wait_for_selector(f'main [data-controller="{cid}"]')


def main(out: Path) -> None:
    exe = chromium_path()
    if exe is None:
        sys.exit("no Chromium: apt-get install chromium (or set MOTIONSIM_CHROMIUM)")
    out.mkdir(parents=True, exist_ok=True)
    with serve() as url, MotionSimClient(url) as ms, sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=exe, headless=True, args=CHROMIUM_ARGS)
        page = browser.new_page(viewport=VIEWPORT, device_scale_factor=1)
        page.goto(f"{url}/dashboard")
        stream_rotary(ms, "p", lines=80, until_s=1.5, cs2_lines=9)
        run_tn20(ms, "t", seconds=0.3)
        page.wait_for_selector('[data-tab="t"]')
        _tab(page, "p")
        for command in ("I16", "I17", "PR"):
            _type(page, "p", command)
        _settle(page, "p", ms)
        page.screenshot(path=str(out / "dashboard-pmac.png"), full_page=True)
        _tab(page, "t")
        for command in ("PRINT MTYPE AXIS(0)", "PRINT NTYPE AXIS(1)", "? VR(101)"):
            _type(page, "t", command)
        _settle(page, "t", ms)
        page.screenshot(path=str(out / "dashboard-trio.png"), full_page=True)
        browser.close()
    print(f"wrote {out / 'dashboard-pmac.png'} and {out / 'dashboard-trio.png'}")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "docs")
