"""Refuse what the controller's number format cannot hold (issue 33 item 7).

``MOVE(1e38)`` gave an ENDMOVE of the wrong sign and ``VR(2)=1e300*1e300`` stored inf
silently. A VR / TABLE store beyond the model's float (32-bit on mc2xx, 64-bit on mc4xx) is a
BASIC error naming the format (REST: 422), and a move argument beyond the axis position counter
(argument × UNITS encoder edges) is refused with nothing buffered (sim/trio/models.py).
"""

from __future__ import annotations

import httpx
import pytest
from motionsim.api.main import create_app
from motionsim.sim.trio.card.models import EDGES_MAX, WORD_MAX

from tests.conftest import dummy_settings, rest_client

pytestmark = pytest.mark.anyio


async def _api(model: str):
    settings = dummy_settings(controllers=[
        {"id": "t", "kind": "trio", "clock": {"mode": "virtual"}, "config": {"model": model}}])
    return rest_client(create_app(settings))


async def _say(api: httpx.AsyncClient, command: str) -> dict:
    return (await api.post("/controllers/t/terminal", json={"command": command})).json()


@pytest.mark.parametrize(("model", "bits"), [("mc2xx", 32), ("mc4xx", 64)])
async def test_vr_and_table_stores_beyond_the_word_are_refused(model, bits) -> None:
    async with await _api(model) as api:
        bad = await _say(api, "VR(2)=1e300*1e300")
        assert f"beyond what the {bits}-bit number format holds" in bad["error"]
        assert (await _say(api, "? VR(2)"))["reply"] == "0.0000"
        assert "number format" in (await _say(api, "TABLE(3)=1e300*1e300"))["error"]
        r = await api.put("/controllers/t/variables/VR(5)", json={"value": WORD_MAX[bits] * 2
                                                                  if bits == 32 else 1e308})
        assert r.status_code == (422 if bits == 32 else 200)
        assert (await _say(api, "VR(6)=-1e30"))["error"] is None  # inside both formats


async def test_a_32_bit_model_refuses_what_only_a_64_bit_one_holds() -> None:
    async with await _api("mc2xx") as api:
        assert "32-bit" in (await _say(api, "VR(3)=1e38*10"))["error"]
    async with await _api("mc4xx") as api:
        assert (await _say(api, "VR(3)=1e38*10"))["error"] is None


@pytest.mark.parametrize(("model", "bits"), [("mc2xx", 32), ("mc4xx", 64)])
async def test_a_move_beyond_the_position_counter_is_refused(model, bits) -> None:
    async with await _api(model) as api:
        bad = await _say(api, "MOVE(1e38)")
        assert f"the {bits}-bit position counter" in bad["error"]
        assert (await _say(api, "? MTYPE"))["reply"] == "0.0000"  # nothing buffered
        limit = EDGES_MAX[bits]
        assert "position counter" in (await _say(api, f"MOVE({limit * 2:.0f})"))["error"]
        assert (await _say(api, "UNITS=1000"))["error"] is None
        too_far = limit / 1000 * 2
        assert "position counter" in (await _say(api, f"MOVE({too_far:.0f})"))["error"]
        assert (await _say(api, "MOVE(1000)"))["error"] is None
        await api.post("/controllers/t/clock/advance", json={"seconds": 0.05})
        assert float((await _say(api, "? ENDMOVE"))["reply"]) == 1000.0
