"""PMAC ``SEND`` lines on the REST terminal (TSRM p470; PSRM p347): the ``output`` list of the
next ``POST .../terminal`` carries every program line sent since the REST terminal's previous
command, whatever its port letter; the event log has the ``plc_send`` / ``program_send``."""

from __future__ import annotations

import pytest

pytestmark = pytest.mark.anyio

BASE = "/controllers/p"


async def test_tsrm_p470_send_lines_come_with_the_next_terminal_reply(pmac_api):
    text = 'P1=P1+1\nIF (P1=2)\nSEND"HOMED 3"\nSENDS"FE WARNING"\nDIS PLC 1\nENDIF'
    assert (await pmac_api.put(f"{BASE}/plcs/1", json={"text": text})).status_code == 200
    r = (await pmac_api.post(f"{BASE}/terminal", json={"command": "I5=2 ENA PLC 1"})).json()
    assert "output" not in r
    await pmac_api.post(f"{BASE}/clock/advance", json={"seconds": 0.01})
    r = (await pmac_api.post(f"{BASE}/terminal", json={"command": "P1"})).json()
    assert r == {"reply": "2", "error": None, "pending": False,
                 "output": ["HOMED 3", "FE WARNING"]}
    r = (await pmac_api.post(f"{BASE}/terminal", json={"command": "P1"})).json()
    assert "output" not in r  # nothing sent since
    events = (await pmac_api.get(f"{BASE}/events", params={"type": "plc_send"})).json()
    assert [(e["plc"], e["port"], e["text"]) for e in events["events"]] == [
        (1, "host", "HOMED 3"), (1, "S", "FE WARNING")]
