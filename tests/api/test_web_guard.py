"""Safe web defaults: Host allow-list (DNS rebinding), Origin checks (CSRF, cross-site
WebSockets), an optional bearer token, CORS off unless configured."""

from __future__ import annotations

import httpx
import pytest
from fastapi.testclient import TestClient
from motionsim.api.main import create_app
from starlette.websockets import WebSocketDisconnect

from tests.conftest import dummy_settings, rest_client

pytestmark = pytest.mark.anyio


async def _client(app, host: str = "127.0.0.1") -> httpx.AsyncClient:
    return httpx.AsyncClient(transport=httpx.ASGITransport(app=app), base_url=f"http://{host}")


@pytest.mark.parametrize("host", ["127.0.0.1", "localhost:8000", "[::1]:8000"])
async def test_loopback_hosts_are_allowed_by_default(make_app, host):
    async with rest_client(make_app()) as api:
        r = await api.get("/controllers", headers={"host": host})
        assert r.status_code == 200


async def test_a_foreign_host_is_refused_dns_rebinding(make_app):
    async with rest_client(make_app()) as api:
        r = await api.post("/controllers/d/clock/advance", json={"seconds": 1},
                           headers={"host": "attacker.example:8000"})
        assert (r.status_code, r.json()["code"]) == (400, "invalid_host")
        assert "MOTIONSIM_ALLOWED_HOSTS" in r.json()["message"]
        assert (await api.get("/controllers/d/clock")).json()["t"] == 0.0


async def test_allowed_hosts_adds_names_and_the_bound_address_is_allowed(make_app):
    async with rest_client(make_app(allowed_hosts=["motionsim"], host="10.1.2.3")) as api:
        for host in ("motionsim:8000", "10.1.2.3:8000", "127.0.0.1"):
            assert (await api.get("/health", headers={"host": host})).status_code == 200
        assert (await api.get("/health", headers={"host": "other"})).status_code == 400


def test_allowed_hosts_from_the_environment_is_comma_separated(monkeypatch):
    monkeypatch.setenv("MOTIONSIM_ALLOWED_HOSTS", "motionsim, sim.local")
    assert dummy_settings().allowed_hosts == ["motionsim", "sim.local"]


async def test_a_cross_site_post_is_refused_and_same_origin_is_not(make_app):
    async with rest_client(make_app()) as api:
        r = await api.post("/controllers/d/clock/advance", json={"seconds": 1},
                           headers={"origin": "http://evil.example"})
        assert (r.status_code, r.json()["code"]) == (403, "forbidden_origin")
        r = await api.post("/controllers/d/clock/advance", json={"seconds": 0.01},
                           headers={"origin": "http://127.0.0.1"})
        assert r.status_code == 200


async def test_cors_is_off_unless_configured(make_app):
    async with rest_client(make_app()) as api:
        r = await api.get("/controllers", headers={"origin": "http://127.0.0.1"})
        assert "access-control-allow-origin" not in r.headers
    async with rest_client(make_app(cors_origins=["http://ui.example"])) as api:
        r = await api.get("/controllers", headers={"origin": "http://ui.example"})
        assert r.headers["access-control-allow-origin"] == "http://ui.example"
        r = await api.options("/controllers", headers={
            "origin": "http://ui.example", "access-control-request-method": "POST"})
        assert r.status_code == 200


async def test_the_token_is_needed_everywhere_but_health(make_app):
    async with rest_client(make_app(token="s3cret")) as api:
        r = await api.get("/controllers")
        assert (r.status_code, r.json()["code"]) == (401, "unauthorized")
        assert r.headers["www-authenticate"] == "Bearer"
        assert (await api.get("/controllers", headers={
            "authorization": "Bearer wrong"})).status_code == 401
        assert (await api.get("/health")).status_code == 200
        assert (await api.get("/controllers", headers={
            "authorization": "Bearer s3cret"})).status_code == 200


async def test_a_token_in_the_query_sets_a_cookie_for_the_dashboard(make_app):
    async with rest_client(make_app(token="s3cret")) as api:
        r = await api.get("/dashboard", params={"token": "s3cret"})
        assert r.status_code == 200
        assert "motionsim_token=s3cret" in r.headers["set-cookie"]
        assert "HttpOnly" in r.headers["set-cookie"]
        r = await api.get("/controllers", headers={"cookie": "motionsim_token=s3cret"})
        assert r.status_code == 200


def test_websockets_check_origin_and_token():
    app = create_app(dummy_settings(allowed_hosts=["testserver"], token="tok"))
    with TestClient(app) as tc:
        with pytest.raises(WebSocketDisconnect) as exc, \
                tc.websocket_connect("/controllers/d/events") as ws:
            ws.receive_text()
        assert exc.value.code == 4401
        with pytest.raises(WebSocketDisconnect) as exc, tc.websocket_connect(
                "/controllers/d/events?token=tok",
                headers={"origin": "http://evil.example"}) as ws:
            ws.receive_text()
        assert exc.value.code == 4403 and "evil.example" in exc.value.reason
        with tc.websocket_connect("/controllers/d/events?token=tok",
                                  headers={"origin": "http://testserver"}) as ws:
            assert ws.receive_json()["type"] == "epoch"


async def test_issue_33_an_origin_on_another_local_port_is_not_the_service(make_app):
    """Issue 33 item 7: any loopback origin on any port was accepted — a page of another local
    app (``http://localhost:9999``) could drive the service. Only the service's own origin (its
    Host, or an allowed host name on its own port) and configured CORS origins pass."""
    async with rest_client(make_app()) as api:  # reached as http://127.0.0.1 (port 80)
        for origin in ("http://localhost:9999", "http://127.0.0.1:8080", "http://[::1]:3000"):
            r = await api.post("/controllers/d/terminal", json={"command": "ECHO x"},
                               headers={"origin": origin})
            assert (r.status_code, r.json()["code"]) == (403, "forbidden_origin"), origin
        for origin in ("http://127.0.0.1", "http://localhost", "http://localhost:80"):
            r = await api.post("/controllers/d/terminal", json={"command": "ECHO x"},
                               headers={"origin": origin})
            assert r.status_code == 200, origin
    async with rest_client(make_app(cors_origins=["http://localhost:9999"])) as api:
        r = await api.post("/controllers/d/terminal", json={"command": "ECHO x"},
                           headers={"origin": "http://localhost:9999"})
        assert r.status_code == 200
