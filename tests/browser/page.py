"""Reading the dashboard page (and the service's log) from the browser tests."""

from __future__ import annotations

from typing import Any

from motionsim.app.client import MotionSimClient


def server_last_seq(ms: MotionSimClient, cid: str) -> int:
    """The newest seq of ``cid``'s log, without reading it: a page asked for beyond the end
    answers with ``reset.last_seq`` (docs/API.md "Epoch")."""
    page = ms.request("GET", f"/controllers/{cid}/events",
                      params={"since": 2**53 - 1, "limit": 1})
    return page["reset"]["last_seq"] if page.get("reset") else page["next"]


def status(page: Any, cid: str) -> dict[str, str]:
    """The stream status line's data: lastSeq, received, gaps, duplicates, reconnects, ..."""
    return page.eval_on_selector(f'[data-controller="{cid}"] [data-role=stream]',
                                 "el => ({...el.dataset})")


def caught_up(b: Any, ms: MotionSimClient, cid: str) -> dict[str, str]:
    """Wait until the page shows controller ``cid`` with every logged event applied."""
    want = server_last_seq(ms, cid)
    b.page.wait_for_function(
        """([cid, want]) => {
             const el = document.querySelector(`[data-controller="${cid}"] [data-role=stream]`);
             return el && el.isConnected && Number(el.dataset.lastSeq) >= want; }""",
        arg=[cid, want])
    return status(b.page, cid)


def select(b: Any, cid: str) -> None:
    """Click controller ``cid``'s tab and wait until it is the one shown."""
    b.page.click(f'[data-tab="{cid}"] button.pick')
    b.page.wait_for_selector(f'main [data-controller="{cid}"]')


def shown(b: Any, cid: str, selector: str) -> str:
    return b.page.inner_text(f'[data-controller="{cid}"] {selector}')
