"""Trio over REST: program output on the REST terminal, programs refused as not simulated or
empty, PMOVE PROC(0) as a Trio reply."""

from __future__ import annotations

import pytest

pytestmark = pytest.mark.anyio

BASE = "/controllers/t"


async def test_terminal_reply_carries_channel_0_lines_printed_since_the_last_command(trio_api):
    await trio_api.put(f"{BASE}/programs/hi", content='PRINT "hello ";HEX(-10)\nPRINT 1/0\n')
    await trio_api.post(f"{BASE}/programs/hi/run", json={"process": 3})
    await trio_api.post(f"{BASE}/clock/advance", json={"seconds": 0.01})
    r = (await trio_api.post(f"{BASE}/terminal", json={"command": "? 2"})).json()
    assert r == {"reply": "2.0000", "error": None, "pending": False,
                 "output": ["hello FFFFF6", "%[Process 3:Line 2] - Divide by zero"]}
    r = (await trio_api.post(f"{BASE}/terminal", json={"command": "? 3"})).json()
    assert "output" not in r  # nothing printed since
    events = (await trio_api.get(f"{BASE}/events", params={"type": "print"})).json()["events"]
    assert [(e["process"], e["channel"], e["text"]) for e in events] == [
        (3, 0, "hello FFFFF6"), (3, 0, "%[Process 3:Line 2] - Divide by zero")
    ]


async def test_program_with_a_command_not_simulated_is_501_not_simulated(trio_api):
    r = await trio_api.put(f"{BASE}/programs/io", content="MOVE(1)\n  PSWITCH(1,ON)\n",
                           headers={"content-type": "text/plain"})
    assert r.status_code == 501  # the service's status for "valid, not simulated"
    body = r.json()
    assert (body["code"], body["line"], body["column"], body["keyword"]) == (
        "not_simulated", 2, 3, "PSWITCH")
    assert "not simulated" in body["message"]
    assert (await trio_api.get(f"{BASE}/programs/io")).status_code == 404


async def test_empty_program_body_is_422_and_not_stored(trio_api):
    r = await trio_api.put(f"{BASE}/programs/empty", content="",
                           headers={"content-type": "text/plain"})
    assert r.status_code == 422 and r.json()["field"] == "body"
    assert (await trio_api.get(f"{BASE}/programs")).json() == {"programs": []}


async def test_not_simulated_at_the_rest_terminal_says_so(trio_api):
    r = (await trio_api.post(f"{BASE}/terminal", json={"command": "BACKLASH(1,2,3)"})).json()
    assert r["not_simulated"] is True and "not simulated" in r["detail"]


async def test_pmove_proc_0_at_the_rest_terminal_is_a_trio_reply(trio_api):
    r = await trio_api.post(f"{BASE}/terminal", json={"command": "PMOVE PROC(0)"})
    assert r.status_code == 200
    r = await trio_api.post(f"{BASE}/terminal", json={"command": "? PMOVE PROC(0)"})
    assert r.status_code == 200 and r.json()["reply"] == "0.0000"
