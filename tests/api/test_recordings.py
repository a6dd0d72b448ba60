"""``GET /controllers/{id}/gather`` (PMAC data gathering) and ``/scope`` (Trio SCOPE): the
recording as JSON columns or CSV, paged like the event log, every sample at its servo-cycle
instant (issue 34 step 3; docs/API.md "Recordings"). Also the LIST GATHER reply over the PMAC
Ethernet port, decoded the way Delta Tau's gathering tool decodes a card's answer."""

from __future__ import annotations

import csv
import io

import pytest
from motionsim.api.pmac_ethernet.protocol import getresponse

from tests.api.pmac_ethernet.test_pmac_server import Client, run
from tests.sim.pmac.test_data_gathering import decode_list_gather

pytestmark = pytest.mark.anyio

P = "/controllers/p"
T = "/controllers/t"


async def term(api, base: str, command: str) -> dict:
    r = await api.post(f"{base}/terminal", json={"command": command})
    assert r.status_code == 200, r.text
    body = r.json()
    assert body["error"] is None, (command, body)
    return body


async def advance(api, base: str, seconds: float) -> None:
    r = await api.post(f"{base}/clock/advance", json={"seconds": seconds})
    assert r.status_code == 200, r.text


async def gather_jog(api) -> None:
    """Motor 1 commanded position (D:$88) and velocity (X:$9D) gathered every 2 servo
    cycles through a jog, then ENDGATHER."""
    await term(api, P, "I5001=$800088 I5002=$40009D I5050=3 I5049=2 I122=20")
    await term(api, P, "DEFINE GATHER 5000")
    await term(api, P, "GATHER")
    await term(api, P, "#1J=500")
    await advance(api, P, 0.4)
    await term(api, P, "ENDGATHER")


async def test_gather_columns_carry_each_samples_servo_cycle_and_instant(pmac_api):
    await gather_jog(pmac_api)
    r = await pmac_api.get(f"{P}/gather", params={"limit": 100_000})
    assert r.status_code == 200
    page = r.json()
    cols = page["columns"]
    period = page["servo_period_s"]
    assert page["kind"] == "gather" and page["running"] is False and page["period_cycles"] == 2
    assert [s["name"] for s in page["sources"]] == ["I5001", "I5002"]
    assert page["sources"][0] == {"name": "I5001", "spec": "$800088", "address": "D:$000088",
                                  "bits": 48, "table_start": None}
    assert page["total"] == len(cols["cycle"]) == page["next"]
    assert all(b - a == 2 for a, b in zip(cols["cycle"], cols["cycle"][1:], strict=False))
    # API.md: every simulated time is written to the nanosecond
    assert cols["t"] == [round(k * period, 9) for k in cols["cycle"]]
    events = (await pmac_api.get(f"{P}/events", params={"type": ["gather", "jog"]})).json()
    by = {(e["type"], e.get("state")): e for e in events["events"]}
    assert cols["t"][0] > by[("gather", "started")]["t"]
    assert cols["t"][-1] <= by[("gather", "stopped")]["t"]
    scale = 96 * 32  # Ixx08 = 96, 1/32 count
    end_t = by[("jog", "end")]["t"]
    after = [v for t, v in zip(cols["t"], cols["I5001"], strict=True) if t >= end_t]
    assert after and set(after) == {500.0 * scale}


async def test_gather_pages_like_the_event_log(pmac_api):
    await gather_jog(pmac_api)
    whole = (await pmac_api.get(f"{P}/gather", params={"limit": 100_000})).json()
    got, since = [], 0
    while True:
        page = (await pmac_api.get(f"{P}/gather", params={"since": since, "limit": 50})).json()
        if page["next"] == since:
            break
        assert len(page["columns"]["cycle"]) <= 50
        got += page["columns"]["cycle"]
        since = page["next"]
    assert got == whole["columns"]["cycle"]


async def test_gather_as_csv_with_accept_text_csv(pmac_api):
    await gather_jog(pmac_api)
    page = (await pmac_api.get(f"{P}/gather", params={"limit": 5})).json()
    r = await pmac_api.get(f"{P}/gather", params={"limit": 5}, headers={"Accept": "text/csv"})
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/csv")
    rows = list(csv.reader(io.StringIO(r.text)))
    assert rows[0] == ["cycle", "t", "I5001", "I5002"]
    assert [int(row[0]) for row in rows[1:]] == page["columns"]["cycle"]
    assert [float(row[1]) for row in rows[1:]] == page["columns"]["t"]


async def test_bad_paging_is_422_naming_the_field(pmac_api):
    for params, field in (({"limit": 0}, "limit"), ({"since": -1}, "since"),
                          ({"limit": "x"}, "limit")):
        r = await pmac_api.get(f"{P}/gather", params=params)
        assert r.status_code == 422
        assert field in r.text


async def test_each_kind_has_its_own_recording_resource(pmac_api, trio_api):
    r = await pmac_api.get(f"{P}/scope")
    assert r.status_code == 404 and "/gather" in r.json()["message"]
    r = await trio_api.get(f"{T}/gather")
    assert r.status_code == 404 and "/scope" in r.json()["message"]


async def test_trio_scope_recording_and_its_table_entries(trio_api):
    await term(trio_api, T, "SCOPE(ON, 4, 100, 140, DPOS AXIS(0), VR(7))")
    await term(trio_api, T, "VR(7)=3")
    await term(trio_api, T, "TRIGGER")
    await term(trio_api, T, "MOVE(10) AXIS(0)")
    await advance(trio_api, T, 0.2)
    page = (await trio_api.get(f"{T}/scope")).json()
    cols = page["columns"]
    assert page["kind"] == "scope" and page["total"] == 20 and page["running"] is False
    assert [s["table_start"] for s in page["sources"]] == [100, 120]
    assert cols["t"] == [round(k * page["servo_period_s"], 9) for k in cols["cycle"]]
    assert cols["VR(7)"] == [3.0] * 20 and cols["DPOS AXIS(0)"][-1] == 10.0
    for j in (0, 19):  # the same numbers through the TABLE variable resource
        r = await trio_api.get(f"{T}/variables/TABLE({120 + j})")
        assert r.json()["value"] == cols["VR(7)"][j]
        r = await trio_api.get(f"{T}/variables/TABLE({100 + j})")
        assert r.json()["value"] == cols["DPOS AXIS(0)"][j]


def test_list_gather_over_pmac_ethernet_decodes_as_a_cards_answer():
    """The reply to ``list gather`` on the Ethernet port (getresponse), decoded as
    dls-pmac-control decodes a card's: the samples the REST recording holds."""

    async def scenario(handle, port):
        c = await Client.connect(port)
        for line in ("i6=1 i3=2", "WY:$1000,$000123", "WX:$1000,$000456",
                     "i5051=0 i5050=$3 i5001=$001000 i5002=$801000 i5049=1 i5000=0",
                     "define gather 6", "gather"):
            await c.ask(line)
        await handle.advance(0.01)
        reply = await c.send(getresponse("list gather"))
        await c.close()
        return reply, handle.controller.recording()

    reply, rec = run(scenario, kind="pmac")
    assert reply.endswith(b"\r\x06")
    text = reply[:-2].decode()
    samples = decode_list_gather(text, [24, 48])
    assert len(samples) == 3 == len(rec.cycles)  # 6 long words, 2 a sample
    assert samples == [[0x123, 0x456 << 24 | 0x123]] * 3


async def test_cycles_are_integers_on_the_wire(pmac_api):
    await gather_jog(pmac_api)
    cols = (await pmac_api.get(f"{P}/gather", params={"limit": 3})).json()["columns"]
    assert all(type(k) is int for k in cols["cycle"])
    assert all(type(v) is float for v in cols["t"] + cols["I5001"])
