"""A page of 100 000 events is encoded in slices (issue 23, item 1): seconds of JSON
encoding never hold the event loop in one go, and the page is what it was — every event in
``EventOut`` form (``t`` a float), ``next`` after the last one."""

from __future__ import annotations

import pytest

from tests.api.loop_gaps import assert_served_beside, with_ticker

pytestmark = pytest.mark.anyio


async def test_a_page_of_100000_events_lets_the_loop_run_while_it_is_encoded(api):
    """The dummy ticker emits a ``tick`` every 10 ms: 995 simulated s hold 99 500."""
    assert (await api.post("/controllers/d/clock/advance", json={"seconds": 995})).is_success
    r, gaps = await with_ticker(api.get("/controllers/d/events", params={"limit": 100000}))
    page = r.json()
    first, last = page["events"][0], page["events"][-1]
    assert r.status_code == 200 and len(page["events"]) > 99000
    assert list(first)[:4] == ["seq", "t", "type", "controller"]
    assert first["seq"] == 1 and isinstance(first["t"], float) and first["controller"] == "d"
    assert page["next"] == last["seq"] == len(page["events"])
    assert_served_beside(gaps)
