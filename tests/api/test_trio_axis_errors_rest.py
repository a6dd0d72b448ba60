"""Over REST: an axis' following-error model set with PATCH (``fe_lag``), its FE in the axis
resource, and the FE_LIMIT trip's events and parameters (TRM p. 8-177, SERVO; docs/trio.md
"Following error and motion errors"); a software-limit stop in the event log (TRM p. 8-177,
RS_LIMIT)."""

from __future__ import annotations

import pytest

pytestmark = pytest.mark.anyio

BASE = "/controllers/t"


async def _ask(api, expr: str) -> float:
    r = await api.post(f"{BASE}/terminal", json={"command": f"? {expr}"})
    return float(r.json()["reply"])


async def test_fe_lag_patch_fe_in_the_axis_resource_and_the_trip(trio_api):
    r = await trio_api.patch(f"{BASE}/axes/0", json={"fe_lag": 0.002})
    assert r.status_code == 200 and r.json()["fe_lag"] == 0.002 and r.json()["fe"] == 0.0
    bad = await trio_api.patch(f"{BASE}/axes/0", json={"fe_lag": 5})
    assert bad.status_code == 422
    for line in ("FE_RANGE=1", "MOVE(100)"):
        await trio_api.post(f"{BASE}/terminal", json={"command": line})
    await trio_api.post(f"{BASE}/clock/advance", json={"seconds": 0.05})
    axis = (await trio_api.get(f"{BASE}/axes/0")).json()
    assert axis["fe"] == pytest.approx(2.0) and axis["dpos"] - axis["mpos"] == pytest.approx(2.0)
    assert int(await _ask(trio_api, "AXISSTATUS")) & 2 == 2
    for line in ("SERVO=ON", "WDOG=ON", "FE_LIMIT=1.5", "MOVE(100)"):
        await trio_api.post(f"{BASE}/terminal", json={"command": line})
    await trio_api.post(f"{BASE}/clock/advance", json={"seconds": 1.0})
    events = (await trio_api.get(f"{BASE}/events",
                                 params={"type": ["following_error", "motion_error"]})).json()
    kinds = [e["type"] for e in events["events"]]
    assert kinds == ["following_error", "motion_error"]
    assert await _ask(trio_api, "MOTION_ERROR") == 1.0 and await _ask(trio_api, "WDOG") == 0.0


async def test_a_software_limit_stop_is_in_the_event_log(trio_api):
    for line in ("FS_LIMIT=50", "MOVE(100)"):
        await trio_api.post(f"{BASE}/terminal", json={"command": line})
    await trio_api.post(f"{BASE}/clock/advance", json={"seconds": 1.0})
    events = (await trio_api.get(f"{BASE}/events", params={"type": "soft_limit"})).json()
    assert [(e["axis"], e["limit"]) for e in events["events"]] == [(0, "FS_LIMIT")]
    assert (await trio_api.get(f"{BASE}/axes/0")).json()["dpos"] == 55.0
