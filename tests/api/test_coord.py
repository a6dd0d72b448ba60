"""PMAC REST resources: coord/{cs}, rotary PUT/DELETE, rotary/lines, run/quit/abort (API.md)."""

from __future__ import annotations

import pytest

from tests.api.conftest import clock_t

pytestmark = pytest.mark.anyio

BASE = "/controllers/p"


async def test_coord_of_a_cs_without_rotary(pmac_api):
    r = await pmac_api.get(f"{BASE}/coord/1")
    assert r.status_code == 200
    assert r.json() == {"cs": 1, "program": {"state": "idle", "line": None, "error": None,
                                             "feed_override": 100.0},
                        "rotary": None}


async def test_coord_shows_the_actual_feedrate_override_that_percent_reports(pmac_api):
    """``%n`` commands the time base; the actual value slews there at Isx94 (TSRM p191): with
    the largest rate it is there in one step, and ``coord`` shows what ``%`` reports."""
    for command in ("I5194=8388607", "&1%50"):
        await pmac_api.post(f"{BASE}/terminal", json={"command": command})
    program = (await pmac_api.get(f"{BASE}/coord/1")).json()["program"]
    reply = (await pmac_api.post(f"{BASE}/terminal", json={"command": "&1%"})).json()["reply"]
    assert program["feed_override"] == pytest.approx(50.0)
    assert float(reply) == pytest.approx(program["feed_override"])


async def test_unknown_cs_is_404(pmac_api):
    r = await pmac_api.get(f"{BASE}/coord/17")
    assert r.status_code == 404 and r.json()["code"] == "not_found"


async def test_coord_routes_on_a_controller_that_is_not_a_pmac_are_404(pmac_api):
    r = await pmac_api.get("/controllers/d/coord/1")
    assert r.status_code == 404 and r.json()["code"] == "not_found"


async def test_define_rotary_and_delete(pmac_api):
    r = await pmac_api.put(f"{BASE}/coord/1/rotary", json={"size_words": 600})
    assert r.status_code == 200
    assert r.json() == {"size_words": 600, "used_words": 0, "free_words": 600,
                        "lines_ahead": 0, "breq": True, "open": False, "full": False}
    assert (await pmac_api.delete(f"{BASE}/coord/1/rotary")).status_code == 204
    assert (await pmac_api.get(f"{BASE}/coord/1")).json()["rotary"] is None


async def test_rest_defined_rotary_counts_as_entered_with_open_rot_breq_high_when_empty(pmac_api):
    """Seed 000: entering a buffer with OPEN ROT takes BREQ low, then high when fewer than I17
    lines are ahead. The REST resource counts as entered, so a REST host waiting for BREQ before
    its first write is asked for lines at once (one rising edge, at the define instant)."""
    r = await pmac_api.put(f"{BASE}/coord/1/rotary", json={"size_words": 600})
    assert (r.json()["breq"], r.json()["open"]) == (True, False)
    ev = (await pmac_api.get(f"{BASE}/events", params={"type": "breq"})).json()["events"]
    assert [(e["cs"], e["level"], e["t"]) for e in ev] == [(1, True, 0.0)]
    coord = (await pmac_api.get(f"{BASE}/coord/1")).json()
    assert coord["rotary"]["breq"] is True and coord["rotary"]["open"] is False


async def test_rest_defined_rotary_with_i17_zero_keeps_breq_low(pmac_api):
    """I17 = 0: no line count is below it, so entering the empty buffer leaves BREQ low."""
    await pmac_api.put(f"{BASE}/variables/I17", json={"value": 0})
    r = await pmac_api.put(f"{BASE}/coord/1/rotary", json={"size_words": 600})
    assert r.json()["breq"] is False
    ev = (await pmac_api.get(f"{BASE}/events", params={"type": "breq"})).json()["events"]
    assert ev == []


async def test_terminal_define_rot_leaves_breq_low_until_open_rot(pmac_api):
    """At the terminal, DEFINE ROT alone does not enter the buffer; OPEN ROT raises BREQ."""
    async def term(command: str) -> None:
        r = await pmac_api.post(f"{BASE}/terminal", json={"command": command})
        assert r.json()["error"] is None

    await term("&1 DEFINE ROT 600")
    assert (await pmac_api.get(f"{BASE}/coord/1")).json()["rotary"]["breq"] is False
    await term("B0 OPEN ROT")
    assert (await pmac_api.get(f"{BASE}/coord/1")).json()["rotary"]["breq"] is True


async def test_define_rotary_out_of_order_is_409_conflict_with_err003(pmac_api):
    """Seed 000: define from the highest-numbered CS down."""
    await pmac_api.put(f"{BASE}/coord/1/rotary", json={"size_words": 20})
    r = await pmac_api.put(f"{BASE}/coord/2/rotary", json={"size_words": 20})
    assert r.status_code == 409
    assert (r.json()["code"], r.json()["pmac_error"]) == ("conflict", "ERR003")


async def test_lines_batch_run_and_events_without_moving_the_clock(pmac_api):
    await pmac_api.put(f"{BASE}/coord/1/rotary", json={"size_words": 600})
    r = await pmac_api.post(f"{BASE}/coord/1/rotary/lines",
                            json={"lines": ["TM100 TA10 TS0 X1", "X2"], "first_seq": 1})
    assert r.status_code == 200
    assert r.json() == {"accepted": 2, "stored": 2, "lines_ahead": 2, "free_words": 595,
                        "breq": True}
    r = await pmac_api.post(f"{BASE}/coord/1/rotary/lines",
                            json={"lines": ["X2", "X3"], "first_seq": 2})
    assert (r.json()["accepted"], r.json()["stored"]) == (2, 1)
    r = await pmac_api.post(f"{BASE}/coord/1/run")
    assert r.json()["program"]["state"] == "running"
    assert await clock_t(pmac_api, BASE) == 0.0
    await pmac_api.post(f"{BASE}/clock/advance", json={"seconds": 1.0})
    ev = (await pmac_api.get(f"{BASE}/events", params={"type": "move_end"})).json()["events"]
    assert [e["n"] for e in ev] == [1, 2, 3]
    coord = (await pmac_api.get(f"{BASE}/coord/1")).json()
    assert coord["program"]["state"] == "waiting"
    assert coord["rotary"]["used_words"] == 0


async def test_bad_line_is_422_with_index_and_column_and_nothing_stored(pmac_api):
    await pmac_api.put(f"{BASE}/coord/1/rotary", json={"size_words": 600})
    r = await pmac_api.post(f"{BASE}/coord/1/rotary/lines", json={"lines": ["X1", "X2 Y@"]})
    assert r.status_code == 422
    body = r.json()
    assert (body["code"], body["index"], body["column"], body["text"], body["pmac_error"]) == (
        "parse_error", 1, 5, "X2 Y@", "ERR003")
    assert (await pmac_api.get(f"{BASE}/coord/1")).json()["rotary"]["lines_ahead"] == 0


async def test_batch_that_does_not_fit_is_409_buffer_full_err006(pmac_api):
    await pmac_api.put(f"{BASE}/coord/1/rotary", json={"size_words": 3})
    r = await pmac_api.post(f"{BASE}/coord/1/rotary/lines", json={"lines": ["X1 Y1", "X2 Y2"]})
    assert r.status_code == 409
    assert (r.json()["code"], r.json()["pmac_error"]) == ("buffer_full", "ERR006")
    ev = (await pmac_api.get(f"{BASE}/events", params={"type": "line_loaded"})).json()
    assert ev["events"] == []


async def test_run_without_rotary_is_409_err015(pmac_api):
    r = await pmac_api.post(f"{BASE}/coord/1/run")
    assert r.status_code == 409 and r.json()["pmac_error"] == "ERR015"


async def test_quit_and_abort(pmac_api):
    await pmac_api.put(f"{BASE}/coord/1/rotary", json={"size_words": 600})
    await pmac_api.post(f"{BASE}/coord/1/rotary/lines", json={"lines": ["TM1000 X10"] * 5})
    await pmac_api.post(f"{BASE}/coord/1/run")
    await pmac_api.post(f"{BASE}/clock/advance", json={"seconds": 0.5})
    r = await pmac_api.post(f"{BASE}/coord/1/abort")
    assert r.json()["program"]["state"] == "aborted"
    r = await pmac_api.post(f"{BASE}/coord/1/run")
    r = await pmac_api.post(f"{BASE}/coord/1/quit")
    await pmac_api.post(f"{BASE}/clock/advance", json={"seconds": 10})
    assert (await pmac_api.get(f"{BASE}/coord/1")).json()["program"]["state"] == "stopped"


async def test_terminal_replies_and_err_codes(pmac_api):
    async def term(cmd):
        return (await pmac_api.post(f"{BASE}/terminal", json={"command": cmd})).json()

    assert await term("I16..17") == {"reply": "5\r10", "error": None, "pending": False}
    assert (await term("X1000"))["error"] == "ERR005"
    assert (await term("&1 DEFINE ROT 100 B0 OPEN ROT"))["error"] is None
    assert await term("X10") == {"reply": "", "error": None, "pending": False}
    assert await term("PR") == {"reply": "1", "error": None, "pending": False}
    assert 0 < await clock_t(pmac_api, BASE) < 0.01


async def test_variables_route(pmac_api):
    r = await pmac_api.put(f"{BASE}/variables/p5", json={"value": 2.5})
    assert r.json() == {"name": "P5", "value": 2.5}
    assert (await pmac_api.get(f"{BASE}/variables/I16")).json() == {"name": "I16", "value": 5.0}
    assert (await pmac_api.get(f"{BASE}/variables/X1")).status_code == 404


async def test_rotary_open_is_true_only_after_open_rot(pmac_api):
    """``rotary.open`` follows ``OPEN ROT`` / ``CLOSE``; ``OPEN PLC n`` leaves it false."""
    await pmac_api.put(f"{BASE}/coord/1/rotary", json={"size_words": 100})

    async def rotary_open() -> bool:
        return (await pmac_api.get(f"{BASE}/coord/1")).json()["rotary"]["open"]

    async def term(command: str) -> None:
        r = await pmac_api.post(f"{BASE}/terminal", json={"command": command})
        assert r.json()["error"] is None

    await term("OPEN PLC 2")
    assert await rotary_open() is False
    await term("CLOSE")
    await term("OPEN ROT")
    assert await rotary_open() is True
    await term("CLOSE")
    assert await rotary_open() is False
