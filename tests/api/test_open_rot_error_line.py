"""``OPEN ROT CLEAR CLOSE`` on one line must not leave the rotary buffer open after its
error (issue 23, item 5): the line's ``CLOSE`` never ran, so the terminal closes what the line
opened; a later program line is then refused on-line (ERR005), not stored by surprise."""

from __future__ import annotations

import pytest

pytestmark = pytest.mark.anyio


async def _say(api, command: str) -> dict:
    r = await api.post("/controllers/p/terminal", json={"command": command})
    return r.json()


async def _rotary(api) -> dict:
    return (await api.get("/controllers/p/coord/1")).json()["rotary"]


@pytest.mark.parametrize("line", ["OPEN ROT X1 P1=(3 CLOSE", "OPEN ROT CLEAR X1 P1=(3 CLOSE",
                                  "OPEN ROT P1=(3 X1 CLOSE"])
async def test_a_failing_line_that_opened_the_rotary_buffer_leaves_it_closed(pmac_api, line):
    await pmac_api.put("/controllers/p/coord/1/rotary", json={"size_words": 100})
    answer = await _say(pmac_api, line)
    assert answer["error"] is not None
    rotary = await _rotary(pmac_api)
    assert rotary["open"] is False and rotary["used_words"] == 0
    after = await _say(pmac_api, "X1")
    assert after["error"] == "ERR005"
    assert (await _rotary(pmac_api))["used_words"] == 0


async def test_a_buffer_opened_on_an_earlier_line_stays_open_after_an_error(pmac_api):
    await pmac_api.put("/controllers/p/coord/1/rotary", json={"size_words": 100})
    assert (await _say(pmac_api, "OPEN ROT"))["error"] is None
    assert (await _say(pmac_api, "X1 P1=(3"))["error"] is not None
    assert (await _rotary(pmac_api))["open"] is True
    assert (await _say(pmac_api, "X2"))["error"] is None
    assert (await _rotary(pmac_api))["used_words"] > 0


async def test_clear_in_the_open_rotary_buffer_is_accepted_and_the_line_closes_it(pmac_api):
    """``CLEAR`` with the rotary open erases its uncalculated lines (a PComm32 host sends
    ``OPEN ROT`` then ``CLEAR``; issue 37 item 5): the line's ``CLOSE`` runs."""
    await pmac_api.put("/controllers/p/coord/1/rotary", json={"size_words": 100})
    assert (await _say(pmac_api, "OPEN ROT CLEAR CLOSE"))["error"] is None
    rotary = await _rotary(pmac_api)
    assert rotary["open"] is False and rotary["used_words"] == 0
