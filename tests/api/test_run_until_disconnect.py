"""A client that disconnects during ``run-until`` leaves no ASGI traceback (issue 33 item 7).

The call's work is cancelled at a slice boundary as before; the route now ends with an
ordinary 499 ``client_closed_request`` answer instead of letting the cancellation escape the
application (uvicorn logged "Exception in ASGI application" with a traceback). Driven at the
ASGI level: the body, then ``http.disconnect`` while the simulation runs.
"""

from __future__ import annotations

import asyncio
import json
import logging

import pytest
from motionsim.api.main import create_app

from tests.conftest import dummy_settings, rest_client

pytestmark = pytest.mark.anyio


@pytest.mark.parametrize(("path", "body"), [
    ("/controllers/p/clock/run-until", {"event": {"type": "terminal_reply"},
                                        "timeout_s": 1e6}),
    ("/controllers/p/clock/advance", {"seconds": 1e6}),
])
async def test_disconnect_mid_call_is_an_answer_not_an_exception(caplog, path, body) -> None:
    settings = dummy_settings(controllers=[{"id": "p", "kind": "pmac",
                                            "clock": {"mode": "virtual"}}])
    app = create_app(settings)
    async with rest_client(app) as api:
        # a PLC scanning keeps the simulation busy (an idle card would jump to the end)
        await api.post("/controllers/p/terminal", json={"command": "I5=2"})
        await api.put("/controllers/p/plcs/1", json={"text": "P1=P1+1"})
        await api.post("/controllers/p/plcs/1/enable")
        raw = json.dumps(body).encode()
        scope = {"type": "http", "asgi": {"version": "3.0"}, "http_version": "1.1",
                 "method": "POST", "scheme": "http", "path": path, "raw_path": path.encode(),
                 "query_string": b"", "root_path": "", "client": ("127.0.0.1", 5),
                 "server": ("127.0.0.1", 80),
                 "headers": [(b"host", b"127.0.0.1"), (b"content-type", b"application/json"),
                             (b"content-length", str(len(raw)).encode())]}
        sent_body = False

        async def receive() -> dict:
            nonlocal sent_body
            if not sent_body:
                sent_body = True
                return {"type": "http.request", "body": raw, "more_body": False}
            await asyncio.sleep(0.3)  # the simulation is running meanwhile
            return {"type": "http.disconnect"}

        messages: list[dict] = []

        async def send(message: dict) -> None:
            messages.append(message)

        with caplog.at_level(logging.DEBUG):
            await asyncio.wait_for(app(scope, receive, send), 30)  # raises nothing
        start = next(m for m in messages if m["type"] == "http.response.start")
        assert start["status"] == 499
        assert not [r for r in caplog.records if r.exc_info]
        # the controller is still usable and its clock stopped where the work stopped
        t = (await api.get("/controllers/p/clock")).json()["t"]
        assert 0 < t < 1e6
        assert (await api.post("/controllers/p/terminal", json={"command": "P1=3 P1"})
                ).json()["reply"] == "3"
