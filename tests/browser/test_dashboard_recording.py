"""The dashboard draws a recording (issue 34 step 4): the PMAC's data gathering loaded from
``GET /controllers/{id}/gather`` as one trace per source against simulated time, then zoomed
to a span. Run against a served motionsim in headless Chromium (tests/browser/conftest.py)."""

from __future__ import annotations

import pytest

from tests.browser.page import select

pytestmark = pytest.mark.timeout(240)

CID = "g"


def _gather(ms) -> dict:
    ms.create_controller("pmac", id=CID, clock="virtual")
    for command in ("I5001=$800088 I5002=$40009D I5050=3 I5049=1 I122=20",
                    "DEFINE GATHER 4000", "GATHER", "#1J=400"):
        assert ms.terminal(CID, command).error is None
    ms.advance(CID, 0.3)
    assert ms.terminal(CID, "ENDGATHER").error is None
    return ms.recording(CID)


def test_a_gather_is_drawn_one_trace_per_source_and_zooms_to_a_span(browser, ms):
    b = browser
    page = _gather(ms)
    b.page.wait_for_selector(f'[data-tab="{CID}"]')
    select(b, CID)
    root = f'[data-controller="{CID}"] [data-role=recording]'
    b.page.click(f"{root} [data-role=recording-load]")
    chart = f"{root} svg[data-role=recording-chart]"
    b.page.wait_for_selector(chart, state="attached")
    names = b.page.eval_on_selector_all(f"{chart} path[data-source]",
                                        "els => els.map((e) => e.dataset.source)")
    assert names == ["I5001", "I5002"]
    assert int(b.page.get_attribute(chart, "data-samples")) == page["total"]
    # each trace draws at most two vertices a pixel column of the plot
    width = float(b.page.get_attribute(chart, "width"))
    for name in names:
        n = int(b.page.get_attribute(f'{chart} path[data-source="{name}"]', "data-vertices"))
        assert 0 < n <= 2 * (width + 1)
    t = page["columns"]["t"]
    t0, t1 = t[len(t) // 4], t[len(t) // 2]
    b.page.fill(f"{root} [data-role=zoom-from]", repr(t0))
    b.page.fill(f"{root} [data-role=zoom-to]", repr(t1))
    b.page.click(f"{root} [data-role=zoom]")
    b.page.wait_for_function(
        """([sel, t0]) => { const el = document.querySelector(sel);
                             return el && Number(el.dataset.t0) === t0; }""", arg=[chart, t0])
    in_span = sum(1 for x in t if t0 <= x <= t1)
    assert int(b.page.get_attribute(chart, "data-samples")) == in_span
    b.page.click(f"{root} [data-role=zoom-all]")
    b.page.wait_for_function(
        """([sel, n]) => { const el = document.querySelector(sel);
                            return el && Number(el.dataset.samples) === n; }""",
        arg=[chart, page["total"]])
    assert b.errors == []
