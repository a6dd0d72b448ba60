"""PMAC PLC programs over REST: GET /plcs, PUT / enable / disable, load figure, watchdog."""

from __future__ import annotations

import asyncio

import pytest
from motionsim.api.pmac_ethernet.protocol import getresponse
from motionsim.api.pmac_ethernet.server import serve_pmac

from tests.api.wire_helpers import connect, serving

pytestmark = pytest.mark.anyio

BASE = "/controllers/p"


async def advance(api, seconds: float) -> None:
    r = await api.post(f"{BASE}/clock/advance", json={"seconds": seconds})
    assert r.status_code == 200


async def test_put_enable_and_list_plc0_scans_once_per_rti(pmac_api):
    r = await pmac_api.put(f"{BASE}/plcs/0", json={"text": "P1=P1+1\nIF (P1>10)\nM1=1\nENDIF"})
    assert r.status_code == 200
    assert r.json()["program"] == ["P1=P1+1", "IF (P1>10)", "M1=1", "ENDIF"]
    assert r.json()["state"] == "disabled"
    r = await pmac_api.post(f"{BASE}/plcs/0/enable")
    assert (r.status_code, r.json()["state"]) == (200, "running")
    await advance(pmac_api, 1.0)
    body = (await pmac_api.get(f"{BASE}/plcs")).json()
    assert body["i5"] == 1
    (plc,) = body["plcs"]
    assert plc["plc"] == 0 and abs(plc["scans"] - 753) <= 1
    assert 0.998 < plc["last_scan_t"] <= 1.0
    ev = (await pmac_api.get(f"{BASE}/events", params={"type": "plc"})).json()["events"]
    assert [(e["plc"], e["state"]) for e in ev] == [(0, "enabled")]


async def test_malformed_text_is_422_with_line_and_column_and_changes_nothing(pmac_api):
    await pmac_api.put(f"{BASE}/plcs/3", json={"text": "P1=1"})
    r = await pmac_api.put(f"{BASE}/plcs/3", json={"text": "P1=2\nIF (P1 >> 2)\nENDIF"})
    assert r.status_code == 422
    body = r.json()
    assert (body["code"], body["line"], body["column"], body["pmac_error"]) == (
        "parse_error", 2, 9, "ERR003")
    assert (await pmac_api.get(f"{BASE}/plcs/3")).json()["program"] == ["P1=1"]


async def test_a_background_plc_needs_i5(pmac_api):
    await pmac_api.put(f"{BASE}/plcs/2", json={"text": "P2=P2+1"})
    r = await pmac_api.post(f"{BASE}/plcs/2/enable")
    assert r.json()["state"] == "enabled"  # I5=1: background PLCs are not permitted
    await pmac_api.put(f"{BASE}/variables/I5", json={"value": 3})
    assert (await pmac_api.get(f"{BASE}/plcs/2")).json()["state"] == "running"
    await advance(pmac_api, 0.1)
    assert (await pmac_api.get(f"{BASE}/variables/P2")).json()["value"] > 100
    r = await pmac_api.post(f"{BASE}/plcs/2/disable")
    assert r.json()["state"] == "disabled"


async def test_terminal_entry_and_err007(pmac_api):
    async def term(cmd: str) -> dict:
        return (await pmac_api.post(f"{BASE}/terminal", json={"command": cmd})).json()

    assert (await term("OPEN PLC 5 CLEAR"))["error"] is None
    # a PLC block closed on its line (PLCs have no one-line IF: PUM p162; this line was
    # the one-line form, which left the IF open)
    assert (await term("IF (M1=0) CMD\"#1J+\" ENDIF")) ["error"] is None
    assert (await term("X10"))["error"] == "ERR003"
    assert (await term("OPEN ROT"))["error"] == "ERR007"
    assert (await term("CLOSE"))["error"] is None
    assert (await pmac_api.get(f"{BASE}/plcs/5")).json()["lines"] == 1


async def test_unknown_plc_or_not_a_pmac_is_404(pmac_api):
    assert (await pmac_api.get(f"{BASE}/plcs/32")).status_code == 404
    r = await pmac_api.get("/controllers/d/plcs")
    assert r.status_code == 404 and r.json()["code"] == "not_found"


async def test_controller_reports_the_cpu_load(pmac_api):
    """Idle card: no motor servo updates, no RTI task, the background cycles every servo cycle.
    Two motors and a 200-statement PLC 0: 2 × 4.4 µs per servo cycle, and 5 + 200 × 3.3 + 2 µs
    of each RTI period (I8 = 2: 3 servo cycles)."""
    period = 1 / 2258.8
    cpu = (await pmac_api.get(BASE)).json()["cpu"]
    assert cpu["servo"] == 0.0 and cpu["rti"] == 0.0 and cpu["background"] == 1.0
    assert cpu["background_cycle_s"] == pytest.approx(period, rel=1e-3)
    await pmac_api.post(f"{BASE}/terminal", json={"command": "&1 #1->X #2->Y"})
    await pmac_api.put(f"{BASE}/plcs/0", json={"text": "\n".join(["P10=P10+1"] * 200)})
    await pmac_api.post(f"{BASE}/plcs/0/enable")
    await advance(pmac_api, 1.5)
    cpu = (await pmac_api.get(BASE)).json()["cpu"]
    assert cpu["servo"] == pytest.approx(2 * 4.4e-6 / period, rel=1e-3)
    assert cpu["rti"] == pytest.approx((5e-6 + 200 * 3.3e-6 + 2e-6) / (3 * period), rel=0.02)
    assert cpu["background"] == pytest.approx(1 - cpu["servo"] - cpu["rti"])


async def test_watchdog_trip_then_reset(pmac_api):
    text = "\n".join(["P10=P10+1"] * 500)
    await pmac_api.put(f"{BASE}/plcs/0", json={"text": text})
    await pmac_api.post(f"{BASE}/plcs/0/enable")
    await advance(pmac_api, 2.0)
    ev = (await pmac_api.get(f"{BASE}/events", params={"type": "watchdog"})).json()["events"]
    assert len(ev) == 1 and ev[0]["t"] == pytest.approx(4097 * 0.00044270837, abs=1e-6)
    r = await pmac_api.post(f"{BASE}/terminal", json={"command": "PR"})
    assert r.status_code == 409 and r.json()["code"] == "watchdog"
    plcs = (await pmac_api.get(f"{BASE}/plcs")).json()["plcs"]
    assert plcs[0]["state"] == "stopped"
    assert (await pmac_api.post(f"{BASE}/reset")).status_code == 200
    r = await pmac_api.post(f"{BASE}/terminal", json={"command": "I5"})
    assert r.json() == {"reply": "1", "error": None, "pending": False}
    assert (await pmac_api.get(f"{BASE}/plcs")).json()["plcs"] == []


async def test_a_trip_aborts_the_running_program_with_error_watchdog(pmac_api):
    """The trip kills the motors: ``coord/1`` shows the program aborted by the watchdog, no
    executing line, and the rotary buffer's calculated lines released."""
    await pmac_api.put(f"{BASE}/coord/1/rotary", json={"size_words": 100})
    await pmac_api.post(f"{BASE}/coord/1/rotary/lines",
                        json={"lines": ["TM1000 X100", "X200", "X300"]})
    await pmac_api.post(f"{BASE}/coord/1/run")
    await pmac_api.put(f"{BASE}/plcs/0", json={"text": "\n".join(["P10=P10+1"] * 500)})
    await pmac_api.post(f"{BASE}/plcs/0/enable")
    await advance(pmac_api, 2.0)
    coord = (await pmac_api.get(f"{BASE}/coord/1")).json()
    assert coord["program"] == {"state": "aborted", "line": None, "error": "watchdog",
                                "feed_override": 100.0}
    assert coord["rotary"]["used_words"] == 0


def test_a_tripped_card_is_silent_on_its_tcp_port():
    """TUM p215: after a watchdog trip the CPU "will not communicate": no bytes come back."""
    async def main() -> tuple[bytes, bytes]:
        async with serving(serve_pmac, "pmac", "p") as (handle, port):
            reader, writer = await connect(port)
            writer.write(getresponse("i3=2 PR"))
            before = await asyncio.wait_for(reader.read(4096), 2.0)
            plcs = handle.controller.plcs
            handle.apply(plcs.load, 0, "\n".join(["P10=P10+1"] * 500))
            handle.apply(plcs.set_enabled, (0,), True)
            handle.clock.advance(2.0)
            writer.write(getresponse("PR"))
            try:
                after = await asyncio.wait_for(reader.read(4096), 0.3)
            except TimeoutError:
                after = b""
            writer.close()
            return before, after

    before, after = asyncio.run(main())
    assert before == b"0\r\x06"
    assert after == b""


async def test_compiled_plcs_are_listed_beside_the_interpreted_ones(pmac_api):
    """PUM-V p238, p245: compiled PLCs (OPEN PLCC n) in ``compiled_plcs``, marked compiled;
    DELETE PLCC takes one out."""
    for line in ["I5=2", "OPEN PLCC 4 CLEAR", "P4=P4+1", "CLOSE", "OPEN PLC 2 CLEAR", "P2=1",
                 "CLOSE", "ENABLE PLCC 4"]:
        r = (await pmac_api.post(f"{BASE}/terminal", json={"command": line})).json()
        assert r["error"] is None, line
    await advance(pmac_api, 0.01)
    body = (await pmac_api.get(f"{BASE}/plcs")).json()
    assert [(p["plc"], p["compiled"]) for p in body["plcs"]] == [(2, False)]
    (plcc,) = body["compiled_plcs"]
    assert (plcc["plc"], plcc["compiled"], plcc["state"], plcc["lines"]) == (4, True, "running", 1)
    assert plcc["scans"] > 0
    await pmac_api.post(f"{BASE}/terminal", json={"command": "DELETE PLCC 4"})
    assert (await pmac_api.get(f"{BASE}/plcs")).json()["compiled_plcs"] == []
